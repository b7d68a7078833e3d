// The Gaussian blur against a direct 2-D sum over the cut and renormalised kernel, and its limits:
// a constant image stays constant (edges too), an impulse spreads with variance ~sigma^2.
#include <gtest/gtest.h>

#include <cmath>

#include "core/util/error.h"
#include "libs/image/gaussian_blur.h"

namespace facetool {
namespace {

// Direct evaluation: every output pixel the weighted mean of the input pixels within 3 sigma
// (rounded up) in x and in y, weights exp(-(dx^2 + dy^2) / (2 sigma^2)), over the pixels inside.
std::vector<float> reference(const std::vector<float>& in, int channels, int w, int h, double sigma) {
  const int r = static_cast<int>(std::ceil(3 * sigma));
  std::vector<float> out(in.size());
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double sum = 0, weight = 0;
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
            const double g = std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
            sum += g * in[(c * h + yy) * w + xx];
            weight += g;
          }
        out[(c * h + y) * w + x] = static_cast<float>(sum / weight);
      }
  return out;
}

std::vector<float> pattern(int channels, int w, int h) {
  std::vector<float> v(static_cast<size_t>(channels) * w * h);
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<float>(std::sin(0.7 * i) * std::cos(0.013 * i * i));
  return v;
}

TEST(GaussianBlur, MatchesDirectSumOnOddShapes) {
  for (double sigma : {0.4, 1.0, 1.5, 3.0})
    for (auto [w, h] : {std::pair{1, 1}, {7, 5}, {13, 31}, {33, 2}}) {
      const std::vector<float> in = pattern(3, w, h);
      const std::vector<float> got = gaussian_blur(in, 3, w, h, sigma), want = reference(in, 3, w, h, sigma);
      for (size_t i = 0; i < got.size(); ++i)
        ASSERT_NEAR(got[i], want[i], 1e-5) << "sigma " << sigma << " " << w << "x" << h << " at " << i;
    }
}

TEST(GaussianBlur, ConstantStaysConstantAndImpulseSpreadsBySigma) {
  const int w = 41, h = 41;
  std::vector<float> flat(w * h, 0.25f);
  for (float v : gaussian_blur(flat, 1, w, h, 2.0)) ASSERT_NEAR(v, 0.25f, 1e-6);
  std::vector<float> impulse(w * h, 0.0f);
  impulse[20 * w + 20] = 1.0f;
  const std::vector<float> b = gaussian_blur(impulse, 1, w, h, 2.0);
  double total = 0, var_x = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      total += b[y * w + x];
      var_x += b[y * w + x] * (x - 20) * (x - 20);
    }
  EXPECT_NEAR(total, 1.0, 1e-5);
  EXPECT_NEAR(var_x, 4.0, 0.1);  // sigma^2, less the tails cut at 3 sigma (~1 %)
  EXPECT_EQ(gaussian_blur(impulse, 1, w, h, 0.0), impulse);
}

TEST(GaussianBlur, RefusesBadArguments) {
  std::vector<float> v(12, 1.0f);
  EXPECT_THROW(gaussian_blur(v, 1, 3, 3, 1.0), Error);
  EXPECT_THROW(gaussian_blur(v, 1, 3, 4, -1.0), Error);
  EXPECT_THROW(gaussian_blur(v, 1, 3, 4, NAN), Error);
}

}  // namespace
}  // namespace facetool
