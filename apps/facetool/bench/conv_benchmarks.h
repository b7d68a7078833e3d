// `bench conv`: the cpu backend's convolution algorithms timed on the network's layer shapes.
#pragma once

#include <ostream>
#include <vector>

#include "core/backend/backend.h"

namespace facetool {

struct ConvBenchOptions {
  int width = 32;
  int input_size = 64;
  std::vector<int> batches{1, 20};
  int repeats = 5;
  bool save = false;  // write the fastest algorithm per shape to the per-machine cache
};

// Times im2col + SGEMM, Winograd and oneDNN's convolution primitive on every convolution shape
// of the paper network at `width` / `input_size`, prints ms and GFLOP/s per layer shape, the
// network's convolution total, and (with `save`) records the winners (cpu_conv_choice.h).
void run_conv_benchmarks(Backend& backend, const ConvBenchOptions& options, std::ostream& out);

}  // namespace facetool
