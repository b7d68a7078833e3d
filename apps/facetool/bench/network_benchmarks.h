// Network benchmarks: forward ms/image and training steps of a network plugin on one backend.
#pragma once

#include <ostream>
#include <vector>

#include "core/plugin/network_plugin.h"

namespace facetool {

struct NetworkBenchOptions {
  std::vector<int> forward_batches{1, 20};
  int train_batch = 20;  // 0: skip the training step
  int repeats = 3;       // timed runs per figure (after one warm-up); the median is printed
  bool compare_plain = true;  // also time eval on the plain ops (FACETOOL_PLAIN_OPS=1's path)
  // cpu backend: time the fused forward at the largest forward batch with several images per
  // chunk (one, the rule's, twice the rule's, the whole batch; alternated) and record the fastest
  // in this machine's cache (cpu_conv_choice.h), which later forwards follow.
  bool save_chunk = false;
};

// Prints forward ms/image (eval mode) at each batch and the training step time (training-mode
// forward, a loss over all four outputs, backward, Adam) in images/s, with GFLOP/s estimated
// from `forward_gflop_per_image` (backward counted as twice the forward); with save_chunk, also
// the chunk table and the choice saved.
void run_network_benchmarks(NetworkPlugin& net, Backend& backend, double forward_gflop_per_image,
                            const NetworkBenchOptions& options, std::ostream& out);

}  // namespace facetool
