// Training augmentation: a fraction of a batch's samples seen in a left-right mirror, labels and all.
#pragma once

#include <cstdint>

#include "libs/data/dataset_reader.h"

namespace facetool {

// Whether row `row` of the batch drawn at `step` for source number `source` is mirrored: row_hash
// (libs/train/grey_inputs.h) under another seed than the grey and relit rows', against `fraction`.
bool mirrored_row(uint64_t seed, int64_t step, int source, int64_t row, double fraction);

// Mirrors, in place, the rows of `batch` that mirrored_row picks: every image-shaped tensor
// (image, albedo, normal, mask, visibility, the input prior) flipped left to right; the normal's
// and the prior normal's x component negated; the SH coefficients odd in x of the visibility and
// the light (sh::mirror_x_sign) negated. So the sample is the same face and light seen in a
// mirror, and every loss term holds for it as for the original. Empty tensors (labels a source
// does not have) stay empty. `first_row`: the batch row of the batch's row 0 (a rank's slice
// starts there).
void mirror_some_rows(SyntheticBatch& batch, uint64_t seed, int64_t step, int source, double fraction,
                      int64_t first_row = 0);

}  // namespace facetool
