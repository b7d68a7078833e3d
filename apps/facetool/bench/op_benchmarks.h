// Op micro-benchmarks at the paper's layer shapes, for any backend (`facetool bench ops`).
#pragma once

#include <ostream>
#include <vector>

#include "core/backend/backend.h"

namespace facetool {

// Times forward and backward of each layer shape at each batch size (median of `repeats` runs
// after one warm-up) and prints one table row per shape x batch x direction with ms and
// GFLOP/s. The last row printed is the 3x3 128->128 convolution forward at batch 20 when 20 is
// among `batches`.
void run_op_benchmarks(Backend& backend, const std::vector<int>& batches, int repeats,
                       std::ostream& out);

}  // namespace facetool
