// `facetool relight` on photos: decompose each face once, then per new light render and paste back.
#include "apps/facetool/relight/relight_pipeline.h"

#include <algorithm>

#include "core/face/frame_rotation.h"
#include "core/face/landmark_drawing.h"
#include "core/face/photo_reader.h"
#include "core/light/light_preview.h"
#include "core/sh/sh_rotation.h"
#include "core/util/error.h"

namespace facetool {
namespace {

std::vector<float> to_planar(const RgbImage& image) {
  const size_t plane = static_cast<size_t>(image.width) * image.height;
  std::vector<float> planar(plane * 3);
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) planar[c * plane + p] = image.pixels[p * 3 + c];
  return planar;
}

sh::Mat3 transpose(const sh::Mat3& m) {
  sh::Mat3 t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[i][j] = m[j][i];
  return t;
}

}  // namespace

DecomposedPhoto decompose_photo(const std::string& path, FaceDetector& detector, Decomposer& decomposer,
                                Backend& backend, int crop_size, const PhotoInferOptions& options) {
  DecomposedPhoto out;
  out.photo = read_photo(path);
  const std::vector<DetectedFace> faces = detector.detect(out.photo, options.detection);
  check(!faces.empty(), "photo '", path, "': ", no_face_reason(out.photo, options.detection));
  std::vector<float> inputs;
  for (const DetectedFace& f : faces) {
    out.crops.push_back(crop_face(out.photo, f, crop_size, options.extend_forehead));
    inputs.insert(inputs.end(), out.crops.back().rgb.begin(), out.crops.back().rgb.end());
  }
  const Decomposition d = decompose_all(decomposer, backend, inputs, static_cast<int>(faces.size()),
                                        crop_size, options.batch);
  return assemble_decomposed_photo(path, std::move(out.photo), std::move(out.crops), d, options.feather);
}

DecomposedPhoto assemble_decomposed_photo(const std::string& path, RgbImage photo, std::vector<FaceCrop> crops,
                                          const Decomposition& decomposition, double feather) {
  DecomposedPhoto out;
  out.path = path;
  out.photo = std::move(photo);
  out.crops = std::move(crops);
  out.decomposition = decomposition;
  const int n = decomposition.count, crop_size = decomposition.size;
  check(n == static_cast<int>(out.crops.size()), "relight: ", n, " decomposed faces for ", out.crops.size(), " crops");
  out.crop_size = crop_size;
  const int w = out.photo.width, h = out.photo.height;
  const size_t plane = static_cast<size_t>(w) * h, crop_plane = static_cast<size_t>(crop_size) * crop_size;
  out.alpha.assign(plane, 0.0f);
  out.old_shading.assign(plane * 3, 1.0f);
  const std::vector<float> ones(crop_plane, 1.0f);
  for (int k = 0; k < n; ++k) {
    const Similarity2& t = out.crops[k].alignment.photo_to_crop;
    out.regions.push_back(paste_region(w, h, t, crop_size, out.crops[k].mask_polygon, feather));
    paste_channels(out.regions.back(), ones.data(), 1, out.alpha.data(), w, h);
    paste_channels(out.regions.back(), out.decomposition.shading.data() + k * 3 * crop_plane, 3,
                   out.old_shading.data(), w, h);
    sh::RgbLight light;
    for (int i = 0; i < sh::kLightCoeffCount; ++i)
      light[i] = out.decomposition.light[static_cast<size_t>(k) * sh::kLightCoeffCount + i];
    out.photo_lights.push_back(rotate_light_to_photo(light, t));
  }
  return out;
}

RelitPhoto relight_photo(const DecomposedPhoto& photo, const sh::RgbLight& light,
                         const RelightSettings& settings, RendererPlugin& renderer, Backend& backend) {
  const Decomposition& d = photo.decomposition;
  const int n = d.count, s = d.size, w = photo.photo.width, h = photo.photo.height;
  const size_t plane = static_cast<size_t>(w) * h, crop_plane = static_cast<size_t>(s) * s;
  // The new light in each face's crop frame: the inverse of the crop-to-photo turn.
  std::vector<float> lights(static_cast<size_t>(n) * sh::kLightCoeffCount);
  for (int k = 0; k < n; ++k) {
    const sh::Mat3 to_crop = transpose(crop_to_photo_rotation(photo.crops[k].alignment.photo_to_crop));
    const sh::RgbLight crop_light = sh::rotate_light(light, to_crop);
    for (int i = 0; i < sh::kLightCoeffCount; ++i)
      lights[static_cast<size_t>(k) * sh::kLightCoeffCount + i] = static_cast<float>(crop_light[i]);
  }
  std::vector<float> visibility = d.visibility;
  if (!settings.visibility) {
    const sh::ShCoeffs open = relight::open_visibility();
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < sh::kCoeffCount; ++i)
        std::fill_n(visibility.begin() + (static_cast<size_t>(k) * 9 + i) * crop_plane, crop_plane,
                    static_cast<float>(open[i]));
  }
  RenderInputs in{Tensor::from_host(backend, Shape{n, 3, s, s}, d.albedo),
                  Tensor::from_host(backend, Shape{n, 3, s, s}, d.normal),
                  Tensor::from_host(backend, Shape{n, 9, s, s}, visibility),
                  Tensor::from_host(backend, Shape{n, sh::kLightCoeffCount}, lights), Tensor()};
  RenderOutputs rendered;
  renderer.forward(in, rendered);
  const std::vector<float> crop_shading = rendered.shading.to_host(), crop_image = rendered.image.to_host();

  RelitPhoto out;
  out.new_shading.assign(plane * 3, 1.0f);
  std::vector<float> planar = to_planar(photo.photo);
  for (int k = 0; k < n; ++k) {
    paste_channels(photo.regions[k], crop_shading.data() + k * 3 * crop_plane, 3, out.new_shading.data(), w, h);
    if (settings.mode == relight::Mode::Render)
      paste_channels(photo.regions[k], crop_image.data() + k * 3 * crop_plane, 3, planar.data(), w, h);
  }
  if (settings.mode == relight::Mode::Ratio)
    relight::apply_ratio(planar.data(), photo.old_shading.data(), out.new_shading.data(), plane,
                         settings.ratio_epsilon, planar.data());
  out.image = planar_rgb(planar.data(), w, h);
  return out;
}

RgbImage shading_over_photo(const DecomposedPhoto& photo, const std::vector<float>& shading) {
  RgbImage out = photo.photo;
  const size_t plane = photo.alpha.size();
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c)
      out.pixels[p * 3 + c] = photo.alpha[p] * shading[c * plane + p] + (1 - photo.alpha[p]) * out.pixels[p * 3 + c];
  return out;
}

RgbImage side_by_side(const std::vector<RgbImage>& tiles, int height) {
  constexpr int kGap = 2;
  std::vector<RgbImage> scaled;
  int width = 0;
  for (const RgbImage& t : tiles) {
    const int tw = std::max(1, static_cast<int>(static_cast<long>(t.width) * height / std::max(1, t.height)));
    scaled.push_back(resize_to_width(t, tw));
    width += tw + (width ? kGap : 0);
  }
  RgbImage sheet;
  sheet.width = width;
  sheet.height = height;
  sheet.pixels.assign(static_cast<size_t>(width) * height * 3, 1.0f);
  int x0 = 0;
  for (const RgbImage& t : scaled) {
    for (int y = 0; y < std::min(height, t.height); ++y)
      std::copy_n(t.at(0, y), static_cast<size_t>(t.width) * 3, sheet.at(x0, y));
    x0 += t.width + kGap;
  }
  return sheet;
}

RgbImage light_sphere(const sh::RgbLight& light, int size) {
  const light::LightPreview preview = light::render_light_preview(light, size);
  RgbImage sphere;
  sphere.width = sphere.height = size;
  sphere.pixels.resize(static_cast<size_t>(size) * size * 3);
  for (int y = 0; y < size; ++y) std::copy_n(preview.image.at(0, y), static_cast<size_t>(size) * 3, sphere.at(0, y));
  return sphere;
}

void draw_light_sphere(RgbImage& image, const sh::RgbLight& light, int size) {
  size = std::min({size, image.width, image.height});
  if (size < 16) return;
  const RgbImage sphere = light_sphere(light, size);
  const int x0 = image.width - size;
  for (int y = 0; y < size; ++y) std::copy_n(sphere.at(0, y), static_cast<size_t>(size) * 3, image.at(x0, y));
}

}  // namespace facetool
