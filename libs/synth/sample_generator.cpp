// One sample from a seed: the generator's pipeline in order.
#include "libs/synth/sample_generator.h"

#include <xmmintrin.h>

#include <algorithm>
#include <cstdio>

#include "libs/image/border_fill.h"
#include "libs/synth/gbuffer.h"
#include "libs/synth/generator_settings.h"
#include "libs/synth/ray_scene.h"
#include "core/util/error.h"
#include "core/util/cpu_time.h"

namespace facetool {
namespace {


// Flush-to-zero and denormals-are-zero while generating (Embree traverses much faster with them;
// every thread sets the same mode, so results do not depend on the thread). Restored after.
class DenormalModeGuard {
 public:
  DenormalModeGuard() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }  // FTZ | DAZ
  ~DenormalModeGuard() { _mm_setcsr(saved_); }
  DenormalModeGuard(const DenormalModeGuard&) = delete;
  DenormalModeGuard& operator=(const DenormalModeGuard&) = delete;

 private:
  unsigned saved_;
};

// Sub-streams of a sample's seed: changing how one part draws never shifts the others.
enum Stream : uint64_t { kShape = 1, kAlbedo, kPose, kCamera, kLight, kBackground, kPhotoEdge, kAlbedoTexture };

const FaceMesh& reference_mesh(const FaceSource& faces) {
  check((faces.model != nullptr) != (faces.mesh != nullptr),
        "SampleGenerator: give either a face model or a mesh");
  return faces.model ? faces.model->neutral() : *faces.mesh;
}

std::string describe_shape(const FaceModel& model, const ShapeWeights& weights) {
  std::string text = "identity[";
  char buffer[64];
  for (size_t k = 0; k < weights.identity.size(); ++k) {
    std::snprintf(buffer, sizeof(buffer), "%s%.4g", k ? " " : "", weights.identity[k]);
    text += buffer;
  }
  text += "] expressions[";
  bool first = true;
  for (size_t k = 0; k < weights.expression.size(); ++k) {
    if (weights.expression[k] == 0.0f) continue;
    std::snprintf(buffer, sizeof(buffer), "%s%s=%.4g", first ? "" : " ",
                  model.expression_names()[k].c_str(), weights.expression[k]);
    text += buffer;
    first = false;
  }
  return text + "]";
}

// Renders `pixels` (albedo and normal from `s`, visibility from `visibility_planes`; gathered
// into compact planes) and scatters the result into `image`, leaving other pixels alone.
// Returns the largest channel value rendered.
float render_masked(const ComponentRenderer& renderer, const SynthSample& s,
                    const std::vector<float>& visibility_planes, const std::vector<int>& pixels,
                    const sh::RgbLight& light, std::vector<float>& image) {
  const int n = static_cast<int>(pixels.size());
  if (n == 0) return 0.0f;
  const size_t plane = s.plane();
  std::vector<float> albedo(3 * n), normal(3 * n), visibility(9 * n), out(3 * n);
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) {
      albedo[c * n + k] = s.albedo[c * plane + pixels[k]];
      normal[c * n + k] = s.normal[c * plane + pixels[k]];
    }
    for (int i = 0; i < 9; ++i) visibility[i * n + k] = visibility_planes[i * plane + pixels[k]];
  }
  renderer.render(n, albedo.data(), normal.data(), visibility.data(), light, out.data());
  float peak = 0.0f;
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) {
      image[c * plane + pixels[k]] = out[c * n + k];
      peak = std::max(peak, out[c * n + k]);
    }
  return peak;
}

}  // namespace

SampleGenerator::SampleGenerator(FaceSource faces, std::vector<LightSource> lights,
                                 BackgroundSource backgrounds,
                                 std::shared_ptr<const ComponentRenderer> renderer,
                                 SynthSettings settings)
    : faces_(std::move(faces)),
      lights_(std::move(lights)),
      backgrounds_(std::move(backgrounds)),
      renderer_(std::move(renderer)),
      settings_(settings),
      albedo_model_(reference_mesh(faces_),
                    faces_.model ? faces_.model->landmarks() : std::vector<int32_t>{}),
      visibility_(settings.direction_count) {
  check(!lights_.empty(), "SampleGenerator: no light sources");
  check(renderer_ != nullptr, "SampleGenerator: no renderer");
  check(settings_.camera.width > 0 && settings_.camera.height > 0, "image size must be positive, got ",
        settings_.camera.width, "x", settings_.camera.height);
  check(settings_.photo_edges.fraction >= 0 && settings_.photo_edges.fraction <= 1,
        "the fraction of samples with a photo edge must be in [0, 1], got ", settings_.photo_edges.fraction);
  check(settings_.photo_edges.fraction == 0 || settings_.camera.framing.border == BorderFill::kRingMean,
        "simulated photo edges need a framing with the ring-mean border fill (the fill they ",
        "reproduce); the framing is '", framing_text(settings_.camera.framing), "'");
  check(!settings_.albedo_textures || settings_.albedo_textures->empty() || faces_.model,
        "albedo textures need the ICT face model (they live in its neutral face's frame), not a fixed mesh");
  settings_description_ = describe_generator_settings(*this);
  settings_fingerprint_ = facetool::settings_fingerprint(settings_description_);
}

SynthSample SampleGenerator::generate(uint64_t run_seed, int64_t index) const {
  const DenormalModeGuard denormal_mode;
  SynthSample s;
  s.run_seed = run_seed;
  s.index = index;
  s.sample_seed = derive_seed(run_seed, static_cast<uint64_t>(index));
  s.settings = settings_fingerprint_;
  auto stream = [&](Stream which) { return Random(derive_seed(s.sample_seed, which)); };
  const double start = thread_cpu_seconds();
  auto since = [](double begin) { return thread_cpu_seconds() - begin; };

  // Shape and albedo.
  FaceMesh mesh;
  if (faces_.model) {
    Random random = stream(kShape);
    const ShapeWeights weights = faces_.model->sample(random, settings_.shape);
    mesh = faces_.model->build(weights);
    s.shape = describe_shape(*faces_.model, weights);
  } else {
    mesh = *faces_.mesh;
    s.shape = "fixed mesh";
  }
  Random albedo_random = stream(kAlbedo);
  const AlbedoParams albedo_params = sample_albedo(albedo_random);
  // A photo texture (drawn from its own stream, so the paper's samples are unchanged without).
  const AlbedoTexture* texture = nullptr;
  bool mirror = false;
  Vec3f gain{1, 1, 1};
  if (settings_.albedo_textures && !settings_.albedo_textures->empty()) {
    Random texture_random = stream(kAlbedoTexture);
    const bool use = texture_random.uniform(0.0, 1.0) < settings_.albedo_texture_fraction;
    const auto& textures = *settings_.albedo_textures;
    const size_t pick = std::min(textures.size() - 1, static_cast<size_t>(texture_random.uniform(0.0, 1.0) * textures.size()));
    mirror = texture_random.uniform(0.0, 1.0) < 0.5;
    if (use) {
      texture = &textures[pick];
      const Vec3f mean = mean_albedo(*texture);
      for (int c = 0; c < 3; ++c) gain[c] = mean[c] > 1e-4f ? albedo_params.skin[c] / mean[c] : 1.0f;
      char text[64];
      std::snprintf(text, sizeof text, " mirror %d gain %.6g %.6g %.6g", mirror ? 1 : 0, gain[0], gain[1], gain[2]);
      s.albedo_texture = texture->source + text;
    }
  }

  // Pose and camera.
  Random pose_random = stream(kPose);
  s.pose = sample_pose(pose_random, settings_.pose);
  apply_pose(mesh, s.pose);
  Random camera_random = stream(kCamera);
  const Camera camera = sample_camera(camera_random, settings_.camera);
  s.fov_deg = camera.horizontal_fov_deg;
  s.width = camera.width;
  s.height = camera.height;
  if (faces_.model && faces_.model->landmarks().size() == 68) {
    const std::vector<int32_t>& vertices = faces_.model->landmarks();
    if (std::all_of(vertices.begin(), vertices.end(), [](int32_t v) { return v >= 0; }))
      for (const int32_t v : vertices) {
        const std::array<double, 2> pixel = camera.project(mesh.positions[v]);
        s.landmarks.insert(s.landmarks.end(), {pixel[0], pixel[1]});
      }
  }

  // Geometry buffers and visibility.
  const std::vector<Vec3f> normals = vertex_normals(mesh);
  const RayScene scene(mesh.positions, mesh.triangles);
  const GBuffer g = cast_primary_rays(scene, mesh, normals, camera);
  const size_t plane = s.plane();
  s.image.assign(3 * plane, 0.0f);
  s.albedo.assign(3 * plane, 0.0f);
  s.normal.assign(3 * plane, 0.0f);
  s.mask.assign(plane, 0.0f);
  s.visibility.assign(9 * plane, 0.0f);
  s.depth.assign(plane, 0.0f);
  s.seconds_geometry = since(start);
  const double visibility_start = thread_cpu_seconds();
  // Visibility domain: the face mask dilated by one pixel (covers the eroded mask the losses use
  // and a margin), restricted to head pixels.
  std::vector<uint8_t> domain =
      settings_.visibility_on_whole_head ? g.head : dilate_mask(g.mask, s.width, s.height);
  for (size_t p = 0; p < plane; ++p) domain[p] = domain[p] && g.head[p];
  s.rays_cast += integrate_visibility_image(visibility_, scene, g.position, g.normal, domain,
                                            s.width, s.height, settings_.ray_offset, s.visibility);
  s.seconds_visibility = since(visibility_start);
  const double shading_start = thread_cpu_seconds();
  std::vector<int> head, face;
  for (size_t p = 0; p < plane; ++p) {
    if (!g.head[p]) continue;
    head.push_back(static_cast<int>(p));
    if (g.mask[p]) {
      face.push_back(static_cast<int>(p));
      s.mask[p] = 1.0f;
    }
    s.depth[p] = g.depth[p];
    Vec3f albedo = albedo_model_.evaluate(albedo_params, g.part[p], g.reference[p]);
    if (texture && (g.part[p] == FacePart::kFace || g.part[p] == FacePart::kHeadNeck)) {
      Vec3f painted;
      float weight;
      sample_albedo_texture(*texture, g.reference[p], mirror, painted, weight);
      // Under the texture's weight, the procedural skin of the sample's colour (no lips or brows:
      // the photo has its own).
      const Vec3f skin = albedo_model_.evaluate_skin(albedo_params, g.reference[p]);
      for (int c = 0; c < 3; ++c)
        albedo[c] = std::clamp(weight * painted[c] * gain[c] + (1.0f - weight) * skin[c], 0.0f, 1.0f);
    }
    for (int c = 0; c < 3; ++c) {
      s.albedo[c * plane + p] = albedo[c];
      s.normal[c * plane + p] = g.normal[p][c];
    }
  }
  // The image of head pixels outside the visibility domain (ears, neck, back of the head) uses
  // the open hemisphere: no labels there, only a plausible photo around the face.
  std::vector<float> image_visibility = s.visibility;
  for (int p : head)
    if (!domain[p]) {
      float open[9];
      visibility_.open_hemisphere(g.normal[p], open);
      for (int i = 0; i < 9; ++i) image_visibility[i * plane + p] = open[i];
    }

  // Light: scale so the brightest face-region pixel is the drawn target, then render the head.
  Random light_random = stream(kLight);
  const SampledLight light = sample_light(light_random, lights_, settings_.light);
  const LightSource& source = lights_[light.source];
  s.light_source = source.name;
  const float peak = render_masked(*renderer_, s, image_visibility, face, light.light, s.image);
  const double scale = peak > 0.0f ? light.target_peak / peak : 1.0;
  s.light = scale_light(light.light, scale);
  render_masked(*renderer_, s, image_visibility, head, s.light, s.image);

  // Background outside the head.
  Random background_random = stream(kBackground);
  std::vector<float> background;
  backgrounds_.fill(background_random, camera, source, light, scale, background);
  for (size_t p = 0; p < plane; ++p)
    if (!g.head[p])
      for (int c = 0; c < 3; ++c) s.image[c * plane + p] = background[c * plane + p];

  // A photo edge across the crop: beyond it the fill and the mask of a real photo's crop.
  if (settings_.photo_edges.fraction > 0) {
    Random edge_random = stream(kPhotoEdge);
    const PhotoEdges edges = sample_photo_edges(edge_random, settings_.photo_edges);
    s.photo_edges = edges.count;
    if (edges.count > 0) {
      const std::vector<float> coverage = photo_edge_coverage(edges, s.width, s.height);
      fill_outside_photo(s.image, coverage, s.width, s.height);
      cut_mask_outside_photo(s.mask, coverage);
    }
  }
  if (settings_.camera.framing != CropFraming{}) s.framing = framing_text(settings_.camera.framing);
  s.seconds_shading = since(shading_start);
  return s;
}

}  // namespace facetool
