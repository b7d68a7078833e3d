// The cpu backend's Winograd F(4x4, 3x3) path (3x3 same convolutions with >= 32 channels):
// forward, input gradient and weight gradient against nested loops in double.
#include <gtest/gtest.h>

#include <cmath>

#include "core/backend/registry.h"
#include "core/ops/ops.h"
#include "tests/cpu/conv_reference.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

Backend& cpu() { return get_backend("cpu"); }

Tensor host(const Shape& s, const std::vector<float>& v) { return Tensor::from_host(cpu(), s, v); }

// Sizes that are and are not multiples of the 4x4 tile, a 1x1 image (a single tile that is all
// padding but one pixel), and 40x36 with 3 images: 100 tiles per image, so tasks of 128 tiles
// are cut mid tile-row... and one that spans several tasks per image (72x60: 270 tiles).
struct Case {
  int64_t batch, channels, out_channels, height, width;
};
const Case kCases[] = {{2, 32, 32, 8, 8},  {2, 37, 33, 13, 11}, {1, 32, 40, 1, 1},
                       {1, 33, 32, 5, 23}, {3, 32, 32, 40, 36}, {1, 32, 34, 72, 60}};

std::string describe(const Case& c) {
  return std::to_string(c.batch) + "x" + std::to_string(c.channels) + "x" +
         std::to_string(c.height) + "x" + std::to_string(c.width) + " -> " +
         std::to_string(c.out_channels);
}

// Tolerances: inputs and weights are uniform in [-1, 1], so each output sums 9 * Ci products of
// magnitude <= 1 (values up to ~20); the transforms' float rounding stays below ~1e-5 of that.
constexpr double kAtol = 2e-4, kRtol = 1e-4;

TEST(CpuWinograd, ForwardMatchesNestedLoops) {
  for (const Case& c : kCases) {
    const Shape xs{c.batch, c.channels, c.height, c.width}, ws{c.out_channels, c.channels, 3, 3};
    const auto xv = random_values(xs.numel(), 21), wv = random_values(ws.numel(), 22),
               bv = random_values(c.out_channels, 23);
    const Tensor bias = host(Shape{c.out_channels}, bv);
    const Tensor y = ops::conv2d(host(xs, xv), host(ws, wv), &bias, Conv2dParams{});
    EXPECT_TRUE(all_close(y.to_host(), conv_reference(xv, xs, wv, ws, bv, 1, 1, c.height, c.width),
                          kAtol, kRtol))
        << describe(c);
  }
}

TEST(CpuWinograd, InputGradientMatchesNestedLoopsAndAccumulates) {
  for (const Case& c : kCases) {
    const Shape xs{c.batch, c.channels, c.height, c.width}, ws{c.out_channels, c.channels, 3, 3};
    const Shape ys{c.batch, c.out_channels, c.height, c.width};
    const auto wv = random_values(ws.numel(), 24), dyv = random_values(ys.numel(), 25);
    const Tensor x = host(xs, random_values(xs.numel(), 26));
    const Tensor dx = Tensor::empty(cpu(), xs);
    ops::conv2d_backward(x, host(ws, wv), host(ys, dyv), &dx, nullptr, nullptr, Conv2dParams{},
                         false);
    const auto expected = conv_dx_reference(dyv, xs, wv, ws, 1, c.height, c.width);
    EXPECT_TRUE(all_close(dx.to_host(), expected, kAtol, kRtol)) << describe(c);
    ops::conv2d_backward(x, host(ws, wv), host(ys, dyv), &dx, nullptr, nullptr, Conv2dParams{},
                         true);
    std::vector<float> twice = expected;
    for (float& v : twice) v *= 2.0f;
    EXPECT_TRUE(all_close(dx.to_host(), twice, 2 * kAtol, kRtol)) << describe(c) << " accumulate";
  }
}

TEST(CpuWinograd, WeightGradientMatchesNestedLoopsAndAccumulates) {
  for (const Case& c : kCases) {
    const Shape xs{c.batch, c.channels, c.height, c.width}, ws{c.out_channels, c.channels, 3, 3};
    const Shape ys{c.batch, c.out_channels, c.height, c.width};
    const auto xv = random_values(xs.numel(), 27), dyv = random_values(ys.numel(), 28);
    const Tensor w = host(ws, random_values(ws.numel(), 29));
    const Tensor dw = Tensor::empty(cpu(), ws), db = Tensor::empty(cpu(), Shape{c.out_channels});
    ops::conv2d_backward(host(xs, xv), w, host(ys, dyv), nullptr, &dw, &db, Conv2dParams{},
                         false);
    // dw sums batch * height * width products: scale the tolerance with the count.
    const double atol = kAtol * std::sqrt(double(c.batch * c.height * c.width) / 9.0);
    const auto expected = conv_dw_reference(xv, xs, dyv, ws, 1, c.height, c.width);
    EXPECT_TRUE(all_close(dw.to_host(), expected, atol, kRtol)) << describe(c);
    ops::conv2d_backward(host(xs, xv), w, host(ys, dyv), nullptr, &dw, nullptr, Conv2dParams{},
                         true);
    std::vector<float> twice = expected;
    for (float& v : twice) v *= 2.0f;
    EXPECT_TRUE(all_close(dw.to_host(), twice, 2 * atol, kRtol)) << describe(c) << " accumulate";
  }
}

}  // namespace
}  // namespace facetool::testing
