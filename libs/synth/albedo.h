// Procedural albedo: skin tones from very light to very dark with low-frequency variation,
// lips, brows, eye whites, irises and pupils; linear RGB in [0, 1], deterministic per seed.
// The recipe is documented in docs/synthetic-data.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libs/synth/face_mesh.h"
#include "libs/synth/random.h"

namespace facetool {

// Everything random about one face's albedo.
struct AlbedoParams {
  double melanin = 0.5;          // 0 = very light skin, 1 = very dark skin
  Vec3f skin{0.5f, 0.35f, 0.3f};
  Vec3f lips{0.4f, 0.2f, 0.2f};
  Vec3f hair{0.05f, 0.03f, 0.02f};  // brows
  float brow_density = 0.8f;
  Vec3f iris{0.1f, 0.05f, 0.02f};
  Vec3f sclera{0.7f, 0.66f, 0.6f};
  float variation = 0.08f;          // amplitude of the low-frequency luminance variation
  float redness = 0.06f;            // extra red on cheeks and nose
  Vec3f noise_offset{0, 0, 0};      // where this face samples the shared noise field
};
AlbedoParams sample_albedo(Random& random);

// Feature geometry on the reference (neutral) face, measured once per model.
class AlbedoModel {
 public:
  // `landmarks`: the 68 Multi-PIE landmark vertices of `reference` (empty: skin only, no lips or
  // brows, e.g. for a user's mesh).
  AlbedoModel(const FaceMesh& reference, const std::vector<int32_t>& landmarks);

  // The albedo at a reference-face point of the given part.
  Vec3f evaluate(const AlbedoParams& params, FacePart part, Vec3f reference_point) const;
  // The skin alone there (no lips or brows), clamped to [0, 1].
  Vec3f evaluate_skin(const AlbedoParams& params, Vec3f reference_point) const;

 private:
  Vec3f skin(const AlbedoParams& params, Vec3f p) const;
  float lip_weight(Vec3f p) const;
  float brow_weight(Vec3f p) const;

  bool has_features_ = false;
  float scale_ = 1.0f;  // inter-ocular distance (outer eye corners); lengths are relative to it
  std::vector<std::array<float, 2>> outer_lip_;  // landmarks 48..59, front view (x, y)
  float lip_front_z_ = 0.0f;
  std::array<std::vector<std::array<float, 2>>, 2> brows_;  // 17..21 and 22..26
  float brow_front_z_ = 0.0f;
  std::array<Vec3f, 2> cheeks_{};  // blush centres
  Vec3f nose_tip_{};
  // Per eye (0: +x side, 1: -x side): centre of the inner eyeball shell.
  std::array<Vec3f, 2> eye_centre_{};
  bool has_eyes_ = false;
};

}  // namespace facetool
