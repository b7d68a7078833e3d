// Training augmentation: a fraction of a batch's labelled photos relit by a random one-sided light.
#pragma once

#include <cstdint>

#include "core/sh/sh_types.h"
#include "libs/data/dataset_reader.h"

namespace facetool {

// Whether row `row` of the batch drawn at `step` for source number `source` is relit: row_hash
// (libs/train/grey_inputs.h) under another seed than the grey rows', against `fraction`.
bool relit_row(uint64_t seed, int64_t step, int source, int64_t row, double fraction);

// The new light's shape before its exposure is matched: a distant light of unit power from
// `direction` (unit, camera frame: +X right, +Y up, +Z to the viewer) plus a uniform ambient
// radiance that gives `ambient` times its irradiance to a surface facing it, unoccluded; the
// same in the three channels.
sh::RgbLight one_sided_light(const sh::Vec3& direction, double ambient);

// How the relit rows' new light shades the network's input (DataSource::relight_light).
enum class RelightLight {
  kSh,    // "sh": the light's 9 SH coefficients through the labels' transfer, input and target alike
  kHard,  // "hard": the input gets the distant light's exact shading, the target keeps the SH one
};

// What relit_row's draw gives row `row`: azimuth about the vertical axis uniform in +-75
// degrees from the camera axis, elevation uniform in -10..40 degrees, ambient uniform in
// 0.05..0.4 (one_sided_light). With RelightLight::kHard, a strobe's wider range: azimuth +-90,
// elevation -30..65, ambient 0.02..0.3. Deterministic in its arguments.
struct RelightDraw {
  sh::Vec3 direction{};
  double ambient = 0;
};
RelightDraw relight_draw(uint64_t seed, int64_t step, int source, int64_t row,
                         RelightLight kind = RelightLight::kSh);

// The exact shading of a unit-power distant light from `direction` at a pixel of normal `n` and
// SH visibility `visibility`: max(n.l, 0) times the visibility function in that direction
// (sh::sh_eval, clamped to 0..1), over pi; the sharp terminator and cast shadow that the light's
// 9 coefficients blur.
double hard_direct_shading(const sh::Vec3& n, const sh::ShCoeffs& visibility, const sh::Vec3& direction);

// Relights, in place, the rows of `batch` that relit_row picks, through their labels: in the
// loss mask where a row's label normal is set, image x (new shading / old shading), each
// channel's shading the renderer's (1 / pi) sum_i L_ci transfer_i (core/sh/pixel_transfer.h) of
// the label normal and visibility under the row's light label (old) and relight_draw's light
// (new); the ratio guarded as `relight --mode ratio` does (libs/relight/relight_math.h), at most
// kMaxRelightGain, and eased towards 1 within kRelightFeather pixels of the region's edge (the
// share of region pixels around each pixel) so that no seam is drawn where the region ends
// inside skin. The new light is scaled per channel so that the mean shading over the region
// stays the old one (the photo's exposure and white balance), and it replaces the row's light
// label. Pixels outside the region (background, hair, the fill outside the photo) are unchanged.
// The image is both the network's input and the reconstruction target, so the losses see the
// relit photo; albedo, normal, visibility and mask are unchanged. A row without a light label
// (all zeros) is left as it is. `first_row`: the batch row of the batch's row 0 (a rank's slice
// starts there).
// With RelightLight::kHard the network's input (batch.input_image, set to a copy of the image
// with its relit rows) is relit instead by the light's exact shading (hard_direct_shading plus
// the ambient through the transfer), while batch.image, the losses' target, is relit through the
// SH light as above: the losses ask the network for the SH decomposition of a photo lit by a
// hard light, its albedo free of the sharp terminator and cast shadows it cannot render.
constexpr float kMaxRelightGain = 3.0f;
constexpr int kRelightFeather = 2;
void relight_some_rows(SyntheticBatch& batch, uint64_t seed, int64_t step, int source, double fraction,
                       int64_t first_row = 0, RelightLight kind = RelightLight::kSh);

}  // namespace facetool
