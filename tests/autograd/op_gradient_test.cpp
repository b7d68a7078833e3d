// Finite-difference gradient checks of every differentiable op, on every backend that works here
// (cpu; opencl where a device is found, PoCL in CI).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "core/backend/registry.h"
#include "core/ops/ops.h"
#include "tests/autograd/gradient_check.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

// The backend of the running test (OpGradient and ConvGradient set it from their parameter).
Backend* g_backend = nullptr;
Backend& backend() { return *g_backend; }

std::vector<std::string> gradient_backends() { return available_backends(); }

class OpGradient : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { g_backend = &get_backend(GetParam()); }
};
INSTANTIATE_TEST_SUITE_P(Backends, OpGradient, ::testing::ValuesIn(gradient_backends()));

Tensor rand(const Shape& s, unsigned seed, float lo = -1.0f, float hi = 1.0f) {
  return random_tensor(backend(), s, seed, lo, hi);
}

Tensor like(const Tensor& t) { return Tensor::empty(t.backend(), t.shape()); }

struct ConvCase {
  int kernel, stride;
  int64_t size;
  bool bias;
};

class ConvGradient : public ::testing::TestWithParam<std::tuple<std::string, ConvCase>> {
 protected:
  void SetUp() override { g_backend = &get_backend(std::get<0>(GetParam())); }
};

TEST_P(ConvGradient, InputWeightAndBias) {
  const ConvCase c = std::get<1>(GetParam());
  Conv2dParams p;
  p.stride = c.stride;
  std::vector<Tensor> inputs = {rand(Shape{2, 3, c.size, c.size}, 1),
                                rand(Shape{4, 3, c.kernel, c.kernel}, 2, -0.5f, 0.5f)};
  if (c.bias) inputs.push_back(rand(Shape{4}, 3));
  auto forward = [&](const std::vector<Tensor>& in) {
    return ops::conv2d(in[0], in[1], c.bias ? &in[2] : nullptr, p);
  };
  auto backward = [&](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0]), like(in[1])};
    if (c.bias) g.push_back(like(in[2]));
    ops::conv2d_backward(in[0], in[1], dy, &g[0], &g[1], c.bias ? &g[2] : nullptr, p, false);
    return g;
  };
  EXPECT_TRUE(gradients_match(inputs, forward, backward));
}

INSTANTIATE_TEST_SUITE_P(Kernels, ConvGradient,
                         ::testing::Combine(::testing::ValuesIn(gradient_backends()),
                                            ::testing::Values(ConvCase{1, 1, 6, true}, ConvCase{1, 2, 7, false},
                                                              ConvCase{3, 1, 6, true}, ConvCase{3, 2, 7, true},
                                                              ConvCase{3, 2, 8, false}, ConvCase{7, 1, 9, true},
                                                              ConvCase{7, 2, 9, true})));

TEST_P(OpGradient, Linear) {
  auto forward = [](const std::vector<Tensor>& in) { return ops::linear(in[0], in[1], &in[2]); };
  auto backward = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0]), like(in[1]), like(in[2])};
    ops::linear_backward(in[0], in[1], dy, &g[0], &g[1], &g[2], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{3, 5}, 1), rand(Shape{4, 5}, 2), rand(Shape{4}, 3)},
                              forward, backward));
}

void check_batch_norm(bool training) {
  BatchNormParams p;
  p.training = training;
  auto forward = [p](const std::vector<Tensor>& in) {
    // Fresh running statistics each call, so eval mode sees the same constants every time.
    Tensor rm = Tensor::full(backend(), Shape{3}, 0.2f);
    Tensor rv = Tensor::full(backend(), Shape{3}, 1.5f);
    return ops::batch_norm(in[0], in[1], in[2], rm, rv, p);
  };
  auto backward = [p](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    Tensor rm = Tensor::full(backend(), Shape{3}, 0.2f);
    Tensor rv = Tensor::full(backend(), Shape{3}, 1.5f);
    ops::BatchNormSaved saved;
    ops::batch_norm(in[0], in[1], in[2], rm, rv, p, &saved);
    std::vector<Tensor> g = {like(in[0]), like(in[1]), like(in[2])};
    ops::batch_norm_backward(in[0], in[1], saved, dy, &g[0], &g[1], &g[2], p, false);
    return g;
  };
  GradientCheckOptions o;
  o.step = 3e-3f;
  EXPECT_TRUE(gradients_match(
      {rand(Shape{2, 3, 3, 2}, 1, -2.0f, 2.0f), rand(Shape{3}, 2, 0.5f, 1.5f), rand(Shape{3}, 3)},
      forward, backward, o));
}

TEST_P(OpGradient, BatchNormTraining) { check_batch_norm(true); }
TEST_P(OpGradient, BatchNormEval) { check_batch_norm(false); }

// Values in [-1, -0.1] u [0.1, 1]: away from leaky ReLU's kink at 0.
Tensor away_from_zero(const Shape& s, unsigned seed) {
  std::vector<float> v = random_values(static_cast<size_t>(s.numel()), seed);
  for (float& x : v) x = x >= 0 ? 0.1f + 0.9f * x : -0.1f + 0.9f * x;
  return Tensor::from_host(backend(), s, v);
}

TEST_P(OpGradient, LeakyRelu) {
  auto forward = [](const std::vector<Tensor>& in) { return ops::leaky_relu(in[0], 0.2f); };
  auto backward = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::leaky_relu_backward(in[0], 0.2f, dy, g[0], false);
    return g;
  };
  GradientCheckOptions o;
  o.step = 1e-2f;  // smaller than the 0.1 gap around the kink
  EXPECT_TRUE(gradients_match({away_from_zero(Shape{2, 3, 4, 4}, 1)}, forward, backward, o));
}

TEST_P(OpGradient, Sigmoid) {
  auto forward = [](const std::vector<Tensor>& in) { return ops::sigmoid(in[0]); };
  auto backward = [](const std::vector<Tensor>& in, const Tensor& y, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::sigmoid_backward(y, dy, g[0], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{2, 3, 4, 4}, 1, -3.0f, 3.0f)}, forward, backward));
}

TEST_P(OpGradient, AddMulScale) {
  auto add_fwd = [](const std::vector<Tensor>& in) { return ops::add(in[0], in[1]); };
  auto add_bwd = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0]), like(in[1])};
    ops::add_backward(dy, &g[0], &g[1], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{2, 3, 4}, 1), rand(Shape{2, 3, 4}, 2)}, add_fwd, add_bwd));
  auto mul_fwd = [](const std::vector<Tensor>& in) { return ops::mul(in[0], in[1]); };
  auto mul_bwd = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0]), like(in[1])};
    ops::mul_backward(in[0], in[1], dy, &g[0], &g[1], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{2, 3, 4}, 3), rand(Shape{2, 3, 4}, 4)}, mul_fwd, mul_bwd));
  auto scale_fwd = [](const std::vector<Tensor>& in) { return ops::scale(in[0], -1.7f); };
  auto scale_bwd = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::scale_backward(dy, -1.7f, g[0], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{5, 7}, 5)}, scale_fwd, scale_bwd));
}

TEST_P(OpGradient, ConcatAndSliceChannels) {
  auto forward = [](const std::vector<Tensor>& in) {
    Tensor joined = ops::concat_channels({in[0], in[1]});
    return ops::slice_channels(joined, 1, 3);  // crosses the boundary between the inputs
  };
  auto backward = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    Tensor djoined = Tensor::empty(backend(), Shape{2, 5, 3, 3});
    ops::slice_channels_backward(dy, 1, djoined, false);
    std::vector<Tensor> g = {like(in[0]), like(in[1])};
    ops::concat_channels_backward(djoined, {&g[0], &g[1]}, false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{2, 2, 3, 3}, 1), rand(Shape{2, 3, 3, 3}, 2)}, forward,
                              backward));
}

TEST_P(OpGradient, UpsampleAndGlobalAvgPool) {
  auto up_fwd = [](const std::vector<Tensor>& in) { return ops::upsample_bilinear2x(in[0]); };
  auto up_bwd = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::upsample_bilinear2x_backward(dy, g[0], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{2, 2, 3, 4}, 1)}, up_fwd, up_bwd));
  auto pool_fwd = [](const std::vector<Tensor>& in) { return ops::global_avg_pool(in[0]); };
  auto pool_bwd = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::global_avg_pool_backward(dy, g[0], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{2, 3, 4, 5}, 2)}, pool_fwd, pool_bwd));
}

TEST_P(OpGradient, L2Normalize) {
  auto forward = [](const std::vector<Tensor>& in) { return ops::l2_normalize(in[0]); };
  auto backward = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::l2_normalize_backward(in[0], 1e-12f, dy, g[0], false);
    return g;
  };
  GradientCheckOptions o;
  o.step = 2e-3f;
  EXPECT_TRUE(gradients_match({rand(Shape{2, 3, 3, 3}, 1, 0.3f, 1.0f)}, forward, backward, o));
}

TEST_P(OpGradient, L2NormalizeBelowEps) {
  // Norms below eps: y = x / eps, so dx = dy / eps.
  const float eps = 1.0f;
  auto forward = [eps](const std::vector<Tensor>& in) { return ops::l2_normalize(in[0], eps); };
  auto backward = [eps](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::l2_normalize_backward(in[0], eps, dy, g[0], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{1, 3, 2, 2}, 1, -0.2f, 0.2f)}, forward, backward));
}

TEST_P(OpGradient, SumAndMean) {
  auto sum_fwd = [](const std::vector<Tensor>& in) { return ops::sum(in[0]); };
  auto sum_bwd = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::sum_backward(dy, g[0], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{3, 4, 5}, 1)}, sum_fwd, sum_bwd));
  auto mean_fwd = [](const std::vector<Tensor>& in) { return ops::mean(in[0]); };
  auto mean_bwd = [](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0])};
    ops::mean_backward(dy, g[0], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{3, 4, 5}, 2)}, mean_fwd, mean_bwd));
}

TEST_P(OpGradient, MaskedMse) {
  std::vector<float> mask_values = random_values(2 * 3 * 3, 9, 0.0f, 1.0f);
  mask_values[0] = 0.0f;  // a fully masked-out pixel
  const Tensor mask = Tensor::from_host(backend(), Shape{2, 1, 3, 3}, mask_values);
  auto forward = [&](const std::vector<Tensor>& in) { return ops::masked_mse(in[0], in[1], mask); };
  auto backward = [&](const std::vector<Tensor>& in, const Tensor&, const Tensor& dy) {
    std::vector<Tensor> g = {like(in[0]), like(in[1])};
    ops::masked_mse_backward(in[0], in[1], mask, dy, &g[0], &g[1], false);
    return g;
  };
  EXPECT_TRUE(gradients_match({rand(Shape{2, 3, 3, 3}, 1), rand(Shape{2, 3, 3, 3}, 2)}, forward,
                              backward));
}

}  // namespace
}  // namespace facetool::testing
