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

// What relit_row's draw gives row `row`: azimuth about the vertical axis uniform in +-75
// degrees from the camera axis, elevation uniform in -10..40 degrees, ambient uniform in
// 0.05..0.4 (one_sided_light). Deterministic in its arguments.
struct RelightDraw {
  sh::Vec3 direction{};
  double ambient = 0;
};
RelightDraw relight_draw(uint64_t seed, int64_t step, int source, int64_t row);

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
constexpr float kMaxRelightGain = 3.0f;
constexpr int kRelightFeather = 2;
void relight_some_rows(SyntheticBatch& batch, uint64_t seed, int64_t step, int source, double fraction,
                       int64_t first_row = 0);

}  // namespace facetool
