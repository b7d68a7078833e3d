// Autograd: gradients of composed ops against finite differences, stop_gradient, reuse, errors.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "core/autograd/functions.h"
#include "core/ops/ops.h"
#include "core/util/error.h"
#include "tests/support/finite_difference.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

using testing::all_close;
using testing::central_difference;
using testing::random_tensor;
using testing::random_values;

Backend& cpu() { return get_backend("cpu"); }

float scalar(const ag::Variable& v) { return v.value().to_host().at(0); }

// Central differences of `f` with respect to every element of `input` (restored afterwards).
// Elements where steps of h and h/2 disagree sit next to a kink (leaky ReLU at 0) and come back
// as NaN, to be skipped: the function is not differentiable there.
std::vector<float> numeric_gradient(const std::function<float()>& f, const Tensor& input,
                                    float step) {
  std::vector<float> values = input.to_host();
  std::vector<float> grad(values.size());
  auto difference = [&](size_t i, float h) {
    const double d = central_difference(values[i], h, [&] {
      input.copy_from_host(values);
      return static_cast<double>(f());
    });
    input.copy_from_host(values);
    return d;
  };
  for (size_t i = 0; i < values.size(); ++i) {
    const double coarse = difference(i, step), fine = difference(i, step / 2);
    const bool smooth = std::abs(coarse - fine) <= 1e-3 + 1e-2 * std::abs(fine);
    grad[i] = smooth ? static_cast<float>(fine) : NAN;
  }
  return grad;
}

// A small network-shaped composition: conv -> batch norm -> leaky ReLU -> upsample -> conv ->
// sigmoid, then a masked MSE against a target plus a pooled branch through a linear layer.
struct Composite {
  ag::Variable x, w1, b1, gamma, beta, w2, fc;
  Tensor running_mean, running_var, target, mask, pool_weights;

  Composite() {
    Backend& be = cpu();
    x = ag::Variable(random_tensor(be, Shape{2, 3, 5, 5}, 1), true);
    w1 = ag::Variable(random_tensor(be, Shape{4, 3, 3, 3}, 2, -0.5f, 0.5f), true);
    b1 = ag::Variable(random_tensor(be, Shape{4}, 3), true);
    gamma = ag::Variable(random_tensor(be, Shape{4}, 4, 0.5f, 1.5f), true);
    beta = ag::Variable(random_tensor(be, Shape{4}, 5), true);
    w2 = ag::Variable(random_tensor(be, Shape{2, 4, 1, 1}, 6), true);
    fc = ag::Variable(random_tensor(be, Shape{3, 4}, 7), true);
    running_mean = Tensor::zeros(be, Shape{4});
    running_var = Tensor::full(be, Shape{4}, 1.0f);
    target = random_tensor(be, Shape{2, 2, 6, 6}, 8, 0.0f, 1.0f);
    std::vector<float> m = random_values(2 * 36, 9, 0.0f, 1.0f);
    for (float& v : m) v = v > 0.3f ? 1.0f : 0.0f;
    mask = Tensor::from_host(be, Shape{2, 1, 6, 6}, m);
    pool_weights = random_tensor(be, Shape{2, 3}, 10);
  }

  ag::Variable loss() {
    BatchNormParams bn;
    bn.training = true;
    bn.momentum = 0.0f;  // keep the running statistics fixed across repeated evaluations
    Conv2dParams stride2;
    stride2.stride = 2;
    ag::Variable h = ag::conv2d(x, w1, b1, stride2);  // [2,4,3,3]
    h = ag::batch_norm(h, gamma, beta, running_mean, running_var, bn);
    h = ag::leaky_relu(h, 0.2f);
    ag::Variable up = ag::upsample_bilinear2x(h);  // [2,4,6,6]
    ag::Variable img = ag::sigmoid(ag::conv2d(up, w2, ag::Variable()));
    ag::Variable recon = ag::masked_mse(img, ag::Variable(target), mask);
    ag::Variable pooled = ag::linear(ag::global_avg_pool(h), fc, ag::Variable());  // [2,3]
    ag::Variable light = ag::sum(ag::mul(pooled, ag::Variable(pool_weights)));
    return ag::add(recon, ag::scale(light, 0.1f));
  }
};

TEST(Autograd, CompositeGradientsMatchFiniteDifferences) {
  Composite net;
  ag::Variable loss = net.loss();
  loss.backward();
  size_t compared = 0, skipped = 0;
  for (ag::Variable* v : {&net.x, &net.w1, &net.b1, &net.gamma, &net.beta, &net.w2, &net.fc}) {
    ASSERT_TRUE(v->has_grad());
    std::vector<float> numeric =
        numeric_gradient([&] { return scalar(net.loss()); }, v->value(), 4e-3f);
    std::vector<float> analytic = v->grad().to_host();
    for (size_t i = 0; i < numeric.size(); ++i) {
      if (std::isnan(numeric[i])) {
        ++skipped;
        continue;
      }
      ++compared;
      // float32 differences with h = 2e-3: rounding ~1e-7 / h relative to the loss, ~1e-4.
      EXPECT_NEAR(analytic[i], numeric[i], 1e-3 + 2e-2 * std::abs(numeric[i]))
          << "element " << i << " of the parameter of shape " << v->shape().str();
    }
  }
  EXPECT_LT(skipped * 10, compared) << "too many points next to a kink: " << skipped;
}

TEST(Autograd, StopGradientBlocksOneBranchOnly) {
  // y = sum(stop(x) * x): dy/dx = x (the stopped factor is a constant), not 2x.
  ag::Variable x(random_tensor(cpu(), Shape{1, 2, 3, 3}, 11), true);
  ag::Variable y = ag::sum(ag::mul(ag::stop_gradient(x), x));
  y.backward();
  EXPECT_TRUE(all_close(x.grad().to_host(), x.value().to_host(), 1e-7, 0));
}

TEST(Autograd, StoppedInputReceivesNoGradient) {
  ag::Variable v(random_tensor(cpu(), Shape{1, 9, 2, 2}, 12), true);
  ag::Variable n(random_tensor(cpu(), Shape{1, 9, 2, 2}, 13), true);
  ag::Variable y = ag::sum(ag::mul(ag::stop_gradient(v), n));
  y.backward();
  EXPECT_FALSE(v.has_grad());
  EXPECT_TRUE(n.has_grad());
}

TEST(Autograd, RepeatedInputCountsTwice) {
  ag::Variable x(random_tensor(cpu(), Shape{1, 1, 2, 3}, 14), true);
  ag::sum(ag::mul(x, x)).backward();
  std::vector<float> expected = x.value().to_host();
  for (float& v : expected) v *= 2.0f;
  EXPECT_TRUE(all_close(x.grad().to_host(), expected, 1e-6, 1e-6));
}

TEST(Autograd, GradientsAccumulateUntilZeroed) {
  ag::Variable x(random_tensor(cpu(), Shape{1, 1, 2, 2}, 15), true);
  ag::sum(ag::scale(x, 3.0f)).backward();
  ag::sum(ag::scale(x, 3.0f)).backward();
  EXPECT_TRUE(all_close(x.grad().to_host(), std::vector<float>(4, 6.0f), 1e-6, 0));
  x.zero_grad();
  ag::sum(ag::scale(x, 3.0f)).backward();
  EXPECT_TRUE(all_close(x.grad().to_host(), std::vector<float>(4, 3.0f), 1e-6, 0));
}

TEST(Autograd, ConcatAndSliceRouteGradients) {
  ag::Variable a(random_tensor(cpu(), Shape{1, 2, 2, 2}, 16), true);
  ag::Variable b(random_tensor(cpu(), Shape{1, 3, 2, 2}, 17), true);
  ag::Variable cat = ag::concat_channels({a, b});
  // Only channels 1..3 (a's second channel and b's first two) reach the loss, with weight 2.
  ag::sum(ag::scale(ag::slice_channels(cat, 1, 3), 2.0f)).backward();
  EXPECT_TRUE(all_close(a.grad().to_host(), {0, 0, 0, 0, 2, 2, 2, 2}, 1e-7, 0));
  EXPECT_TRUE(all_close(b.grad().to_host(), {2, 2, 2, 2, 2, 2, 2, 2, 0, 0, 0, 0}, 1e-7, 0));
}

TEST(Autograd, BackwardWithoutGradientIsAnError) {
  ag::Variable x(random_tensor(cpu(), Shape{1, 1, 2, 2}, 18), false);
  ag::Variable y = ag::sum(x);
  EXPECT_THROW(y.backward(), Error);
  ag::Variable z(random_tensor(cpu(), Shape{1, 1, 2, 2}, 19), true);
  EXPECT_THROW(ag::scale(z, 2.0f).backward(), Error);  // not a scalar and no seed
}

}  // namespace
}  // namespace facetool
