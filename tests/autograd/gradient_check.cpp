// Finite-difference gradient checking: probe input elements, compare with the backward op.
#include "tests/autograd/gradient_check.h"

#include <cmath>

#include "tests/support/finite_difference.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

double objective(const Tensor& y, const std::vector<float>& r) {
  const std::vector<float> values = y.to_host();
  double total = 0.0;
  for (size_t i = 0; i < values.size(); ++i) total += double(values[i]) * double(r[i]);
  return total;
}

}  // namespace

::testing::AssertionResult gradients_match(std::vector<Tensor> inputs, const ForwardFn& forward,
                                           const BackwardFn& backward,
                                           const GradientCheckOptions& options) {
  const Tensor y = forward(inputs);
  const std::vector<float> r = random_values(static_cast<size_t>(y.numel()), 4242u);
  const Tensor dy = Tensor::from_host(y.backend(), y.shape(), r);
  const std::vector<Tensor> grads = backward(inputs, y, dy);
  for (size_t k = 0; k < grads.size(); ++k) {
    if (!grads[k].defined()) continue;
    std::vector<float> values = inputs[k].to_host();
    const std::vector<float> analytic = grads[k].to_host();
    const size_t stride = std::max<size_t>(1, values.size() / options.max_samples);
    for (size_t i = 0; i < values.size(); i += stride) {
      const double numeric = central_difference(values[i], options.step, [&] {
        inputs[k].copy_from_host(values);
        return objective(forward(inputs), r);
      });
      inputs[k].copy_from_host(values);
      const double error = std::abs(numeric - analytic[i]);
      if (!(error <= options.atol + options.rtol * std::abs(numeric)))
        return ::testing::AssertionFailure()
               << "input " << k << " " << inputs[k].shape().str() << " element " << i
               << ": analytic " << analytic[i] << " vs finite difference " << numeric;
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace facetool::testing
