// Bad input on the cpu backend: clear errors for mismatched or empty tensors, NaN propagation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/backend/registry.h"
#include "core/ops/ops.h"
#include "core/util/error.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

Backend& cpu() { return get_backend("cpu"); }

// Runs fn, expecting a facetool::Error whose message contains every one of `parts`.
template <typename Fn>
void expect_error_naming(Fn fn, const std::vector<std::string>& parts) {
  try {
    fn();
    ADD_FAILURE() << "expected a facetool::Error";
  } catch (const Error& e) {
    const std::string message = e.what();
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing from: " << message;
  }
}

TEST(CpuBadInput, MismatchedShapesNameOpAndShapes) {
  const Tensor a = Tensor::zeros(cpu(), Shape{2, 3});
  const Tensor b = Tensor::zeros(cpu(), Shape{3, 2});
  expect_error_naming([&] { ops::add(a, b); }, {"add", "[2, 3]", "[3, 2]"});
  expect_error_naming([&] { ops::mul(a, b); }, {"mul", "[2, 3]", "[3, 2]"});
  const Tensor x = Tensor::zeros(cpu(), Shape{1, 3, 8, 8});
  const Tensor w = Tensor::zeros(cpu(), Shape{4, 5, 3, 3});
  expect_error_naming([&] { ops::conv2d(x, w, nullptr, Conv2dParams{}); },
                      {"conv2d", "[1, 3, 8, 8]", "[4, 5, 3, 3]"});
  const Tensor pred = Tensor::zeros(cpu(), Shape{1, 3, 4, 4});
  const Tensor target = Tensor::zeros(cpu(), Shape{1, 3, 4, 5});
  expect_error_naming([&] { ops::masked_mse(pred, target, Tensor::zeros(cpu(), Shape{1, 1, 4, 4})); },
                      {"masked_mse", "[1, 3, 4, 4]", "[1, 3, 4, 5]"});
}

TEST(CpuBadInput, EmptyTensorsAreRejected) {
  const Tensor empty = Tensor::empty(cpu(), Shape{0, 3});
  expect_error_naming([&] { ops::sum(empty); }, {"sum", "empty"});
  expect_error_naming([&] { ops::leaky_relu(empty, 0.2f); }, {"leaky_relu", "empty"});
  expect_error_naming([&] { ops::add(empty, empty); }, {"add", "empty"});
}

bool all_nan(const std::vector<float>& v) {
  for (float f : v)
    if (!std::isnan(f)) return false;
  return true;
}

TEST(CpuBadInput, NanInputsPropagate) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Tensor x = Tensor::full(cpu(), Shape{1, 2, 3, 3}, nan);
  EXPECT_TRUE(all_nan(ops::leaky_relu(x, 0.2f).to_host()));
  EXPECT_TRUE(all_nan(ops::sigmoid(x).to_host()));
  EXPECT_TRUE(all_nan(ops::sum(x).to_host()));
  EXPECT_TRUE(all_nan(ops::l2_normalize(x).to_host()));
  EXPECT_TRUE(all_nan(ops::upsample_bilinear2x(x).to_host()));
  EXPECT_TRUE(all_nan(ops::global_avg_pool(x).to_host()));
  const Tensor w = Tensor::full(cpu(), Shape{2, 2, 3, 3}, 0.5f);
  EXPECT_TRUE(all_nan(ops::conv2d(x, w, nullptr, Conv2dParams{}).to_host()));
  // One NaN pixel reaches exactly the outputs whose window covers it.
  std::vector<float> one(18, 1.0f);
  one[4] = nan;  // channel 0, centre pixel
  const Tensor y = ops::conv2d(Tensor::from_host(cpu(), Shape{1, 2, 3, 3}, one), w, nullptr,
                               Conv2dParams{});
  EXPECT_TRUE(all_nan(y.to_host()));  // a 3x3 window at any output covers the centre
  Tensor rm = Tensor::zeros(cpu(), Shape{2}), rv = Tensor::full(cpu(), Shape{2}, 1.0f);
  const Tensor ones = Tensor::full(cpu(), Shape{2}, 1.0f), zeros = Tensor::zeros(cpu(), Shape{2});
  EXPECT_TRUE(all_nan(ops::batch_norm(x, ones, zeros, rm, rv, BatchNormParams{}).to_host()));
  const Tensor mask = Tensor::full(cpu(), Shape{1, 1, 3, 3}, 1.0f);
  EXPECT_TRUE(all_nan(ops::masked_mse(x, Tensor::zeros(cpu(), x.shape()), mask).to_host()));
  Tensor dx = Tensor::empty(cpu(), Shape{1, 2, 3, 3}), dw = Tensor::empty(cpu(), w.shape());
  ops::conv2d_backward(x, w, Tensor::full(cpu(), Shape{1, 2, 3, 3}, 1.0f), &dx, &dw, nullptr,
                       Conv2dParams{}, false);
  EXPECT_TRUE(all_nan(dw.to_host()));
}

}  // namespace
}  // namespace facetool::testing
