// AdamOptimizer: torch.optim.Adam over a list of parameters, with moment buffers on their backend.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/autograd/variable.h"
#include "core/backend/backend.h"
#include "core/backend/op_params.h"

namespace facetool {

class AdamOptimizer {
 public:
  // `params.step` is ignored: the optimizer counts its own steps from 1.
  AdamOptimizer(std::vector<std::pair<std::string, ag::Variable>> parameters, AdamParams params);

  // Updates every parameter that has a gradient, then clears the gradients.
  void step();
  int64_t steps_taken() const { return step_; }
  // Moment buffers by parameter name ("<name>.adam_m", "<name>.adam_v"), for checkpoints.
  std::vector<std::pair<std::string, Tensor>> state() const;
  void set_steps_taken(int64_t steps) { step_ = steps; }

 private:
  struct Slot {
    std::string name;
    ag::Variable parameter;
    Tensor m, v;
  };
  std::vector<Slot> slots_;
  std::vector<Backend::AdamTensors> batch_;  // this step's update list
  AdamParams params_;
  int64_t step_ = 0;
};

}  // namespace facetool
