// `facetool bench train`: a full stage-1 training step (data, network, renderer, eight terms, Adam).
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <vector>

#include "core/backend/backend.h"
#include "core/plugin/loss_plugin.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/renderer_plugin.h"

namespace facetool {

struct TrainBenchOptions {
  std::vector<int> widths = {32, 64, 128};
  int input_size = 128;
  int batch = 20;
  int repeats = 3;  // timed steps after one warm-up step
};

// For each width: images/s of the whole step, and the shares of the loss terms with the
// renderer (forward and backward, timed alone on the same shapes) and of waiting for data.
// The data are 2 x batch generated samples in a temporary folder, removed afterwards.
void run_train_benchmarks(const std::function<std::shared_ptr<NetworkPlugin>()>& make_network,
                          std::shared_ptr<RendererPlugin> renderer,
                          std::shared_ptr<LossPlugin> losses, Backend& backend,
                          const TrainBenchOptions& options, std::ostream& out);

}  // namespace facetool
