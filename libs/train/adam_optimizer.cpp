// AdamOptimizer: moment buffers and the update of all parameters through ops::adam_step_all.
#include "libs/train/adam_optimizer.h"

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
  // One fused update over every parameter with a gradient (one parallel loop on the cpu
  // instead of one per parameter); the list is rebuilt each step, its capacity kept.
  batch_.clear();
  for (Slot& slot : slots_)
    if (slot.parameter.has_grad())
      batch_.push_back({slot.parameter.value(), slot.parameter.grad(), slot.m, slot.v});
  ops::adam_step_all(batch_, p);
  batch_.clear();
  for (Slot& slot : slots_)
    if (slot.parameter.has_grad()) slot.parameter.zero_grad();
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
