// Training augmentation: a fraction of a batch's input photos turned grey (luminance in R, G, B).
#pragma once

#include <cstdint>

#include "core/tensor/tensor.h"

namespace facetool {

// A well-mixed 64-bit hash of (seed, step, source, row): the per-image draws of the training
// augmentations (this one, libs/train/relit_inputs.h and mirrored_inputs.h), the same after a resume.
uint64_t row_hash(uint64_t seed, int64_t step, int source, int64_t row);

// Whether row_hash of these arguments falls below `fraction` (0: never, 1: always): each
// augmentation's pick of rows, under its own seed (the grey rows' `seed`, the others' salted).
bool row_drawn(uint64_t seed, int64_t step, int source, int64_t row, double fraction);

// Whether row `row` of the batch drawn at `step` for source number `source` is turned grey:
// row_hash against `fraction`, so a resumed run greys the same rows.
bool grey_row(uint64_t seed, int64_t step, int source, int64_t row, double fraction);

// `input` ([N, C, H, W], C >= 3: the photo's linear RGB, then any prior channels) with the rows
// grey_row picks given their luminance (libs/io/image_io.h) in their first three channels; the
// other channels and rows are unchanged. `first_row`: the batch row of input's row 0 (a rank's
// slice of the batch starts there), so that every process count greys the same images. Only the
// network's input: the loss targets keep the colour photo.
Tensor grey_some_rows(const Tensor& input, uint64_t seed, int64_t step, int source, double fraction,
                      int64_t first_row = 0);

}  // namespace facetool
