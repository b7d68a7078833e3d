// Central finite-difference gradient checks of an op through the scalar objective sum(r * y).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/tensor/tensor.h"

namespace facetool::testing {

// Computes the op's output from its inputs.
using ForwardFn = std::function<Tensor(const std::vector<Tensor>& inputs)>;
// Returns the gradients of sum(dy * y) for the inputs (an undefined tensor where not checked).
using BackwardFn = std::function<std::vector<Tensor>(const std::vector<Tensor>& inputs,
                                                     const Tensor& y, const Tensor& dy)>;

struct GradientCheckOptions {
  float step = 1e-2f;
  double atol = 2e-3;
  double rtol = 2e-2;
  size_t max_samples = 60;  // input elements probed per input (evenly spread)
};

// Compares every returned analytic gradient with central differences of sum(r * forward(...))
// where r is a fixed random tensor shaped like the output.
::testing::AssertionResult gradients_match(std::vector<Tensor> inputs, const ForwardFn& forward,
                                           const BackwardFn& backward,
                                           const GradientCheckOptions& options = {});

}  // namespace facetool::testing
