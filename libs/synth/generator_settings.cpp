// describe_generator_settings and settings_fingerprint.
#include "libs/synth/generator_settings.h"

#include <cstdint>
#include <cstdio>
#include <sstream>

#include "libs/synth/sample_generator.h"

namespace facetool {
namespace {

struct Fnv1a {
  uint64_t state = 14695981039346656037ull;
  void add(const void* data, size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
      state ^= bytes[i];
      state *= 1099511628211ull;
    }
  }
  std::string hex() const {
    char text[17];
    std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(state));
    return text;
  }
};

std::string mesh_hash(const FaceMesh& mesh) {
  Fnv1a hash;
  hash.add(mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f));
  hash.add(mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]));
  return hash.hex();
}

}  // namespace

std::string settings_fingerprint(const std::string& text) {
  Fnv1a hash;
  hash.add(text.data(), text.size());
  return hash.hex();
}

std::string describe_generator_settings(const SampleGenerator& generator) {
  const SynthSettings& s = generator.settings();
  std::ostringstream out;
  out.precision(17);
  out << "generator " << kSynthGeneratorVersion << "\n"
      << "size " << s.camera.width << "x" << s.camera.height << ", fov " << s.camera.min_fov_deg
      << ".." << s.camera.max_fov_deg << " deg\n"
      << "visibility " << s.direction_count << " directions, ray offset " << s.ray_offset
      << (s.visibility_on_whole_head ? ", whole head" : ", face region") << "\n"
      << "pose max roll " << s.pose.max_roll_deg << " pitch " << s.pose.max_pitch_deg << " yaw "
      << s.pose.max_yaw_deg << "\n"
      << "shape identity truncation " << s.shape.identity_truncation << ", max expressions "
      << s.shape.max_active_expressions << ", max expression weight "
      << s.shape.max_expression_weight << "\n";
  if (!s.shape.fixed_expressions.empty()) {  // only then: older runs' settings text is unchanged
    out << "fixed expressions";
    for (const auto& [name, weight] : s.shape.fixed_expressions) out << " " << name << "=" << weight;
    out << "\n";
  }
  // Only when not v1's: older runs' settings text (and fingerprint) is unchanged.
  if (s.camera.framing != CropFraming{}) out << "framing " << framing_text(s.camera.framing) << "\n";
  if (s.photo_edges.fraction > 0) out << "photo edges in " << s.photo_edges.fraction << " of the samples\n";
  if (s.albedo_textures && !s.albedo_textures->empty()) {
    Fnv1a hash;
    for (const AlbedoTexture& t : *s.albedo_textures) {
      hash.add(t.source.data(), t.source.size());
      hash.add(t.rgb.data(), t.rgb.size() * sizeof(float));
      hash.add(t.weight.data(), t.weight.size() * sizeof(float));
    }
    out << "albedo textures " << s.albedo_textures->size() << " " << hash.hex() << " in "
        << s.albedo_texture_fraction << " of the samples\n";
  }
  out << "light rotate " << s.light.rotate << ", max tilt " << s.light.max_tilt_deg
      << ", colour jitter " << s.light.color_jitter << ", peak " << s.light.min_peak << ".."
      << s.light.max_peak << "\n"
      << "renderer " << generator.renderer().name() << "\n";
  const FaceSource& faces = generator.faces();
  if (faces.model)
    out << "faces ICT model: " << faces.model->identity_count() << " identities, "
        << faces.model->expression_names().size() << " expressions, neutral mesh "
        << mesh_hash(faces.model->neutral()) << "\n";
  else
    out << "faces mesh: " << faces.mesh->positions.size() << " vertices, "
        << faces.mesh->triangles.size() << " triangles, geometry " << mesh_hash(*faces.mesh)
        << "\n";
  for (const LightSource& light : generator.lights()) {
    Fnv1a hash;
    hash.add(light.light.data(), light.light.size() * sizeof(light.light[0]));
    if (light.environment)
      hash.add(light.environment->rgb.data(), light.environment->rgb.size() * sizeof(float));
    out << "light " << light.name << " " << hash.hex() << "\n";
  }
  const BackgroundSource& backgrounds = generator.backgrounds();
  if (!backgrounds.uses_images()) out << "backgrounds: views of the environment\n";
  for (const std::string& image : backgrounds.images()) out << "background " << image << "\n";
  return out.str();
}

}  // namespace facetool
