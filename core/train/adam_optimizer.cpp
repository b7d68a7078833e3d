// AdamOptimizer: moment buffers and the per-parameter update through ops::adam_step.
#include "core/train/adam_optimizer.h"

#include "core/ops/ops.h"

namespace facetool {

AdamOptimizer::AdamOptimizer(std::vector<std::pair<std::string, ag::Variable>> parameters,
                             AdamParams params)
    : params_(params) {
  for (auto& [name, p] : parameters) {
    Backend& be = p.backend();
    slots_.push_back({name, p, Tensor::zeros(be, p.shape()), Tensor::zeros(be, p.shape())});
  }
}

void AdamOptimizer::step() {
  ++step_;
  AdamParams p = params_;
  p.step = step_;
  for (Slot& slot : slots_) {
    if (!slot.parameter.has_grad()) continue;
    ops::adam_step(slot.parameter.value(), slot.parameter.grad(), slot.m, slot.v, p);
    slot.parameter.zero_grad();
  }
}

std::vector<std::pair<std::string, Tensor>> AdamOptimizer::state() const {
  std::vector<std::pair<std::string, Tensor>> out;
  for (const Slot& slot : slots_) {
    out.emplace_back(slot.name + ".adam_m", slot.m);
    out.emplace_back(slot.name + ".adam_v", slot.v);
  }
  return out;
}

}  // namespace facetool
