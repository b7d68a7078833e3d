// Evaluation metrics against closed forms: known angles, PSNR of a known error, SSIM limits.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "libs/train/eval_metrics.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {

TEST(EvalMetrics, NormalAnglesAndTable1Summary) {
  // Four pixels: 0, 10, 22.5 and 45 degrees about the x axis; the fifth is outside the mask.
  const double deg[5] = {0, 10, 22.5, 45, 80};
  const int64_t plane = 5;
  std::vector<float> truth(15, 0.0f), pred(15, 0.0f), mask = {1, 1, 1, 1, 0};
  for (int i = 0; i < 5; ++i) {
    const double r = deg[i] * kPi / 180.0;
    truth[2 * plane + i] = 1.0f;
    pred[1 * plane + i] = static_cast<float>(2.0 * std::sin(r));  // length 2: not normalised
    pred[2 * plane + i] = static_cast<float>(2.0 * std::cos(r));
  }
  std::vector<double> angles;
  normal_angles_deg(pred.data(), truth.data(), mask.data(), plane, angles);
  ASSERT_EQ(angles.size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(angles[i], deg[i], 1e-3);
  const AngularSummary s = summarize_angles(angles);
  EXPECT_NEAR(s.mean, 77.5 / 4, 1e-3);
  const double var = (0 + 100 + 22.5 * 22.5 + 45 * 45) / 4.0 - s.mean * s.mean;
  EXPECT_NEAR(s.std, std::sqrt(var), 1e-3);
  EXPECT_DOUBLE_EQ(s.under20, 50.0);
  EXPECT_DOUBLE_EQ(s.under25, 75.0);
  EXPECT_DOUBLE_EQ(s.under30, 75.0);
}

TEST(EvalMetrics, PsnrOfAConstantErrorAndSsimLimits) {
  const int w = 16, h = 12;
  const int64_t plane = w * h;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.2f, 0.8f);
  std::vector<float> a(3 * plane), b(3 * plane), mask(plane, 1.0f);
  for (float& v : a) v = u(rng);
  for (size_t i = 0; i < a.size(); ++i) b[i] = a[i] + 0.1f;
  mask[0] = 0.0f;
  EXPECT_NEAR(masked_psnr(a.data(), b.data(), mask.data(), w, h), 20.0, 1e-4);  // MSE 0.01
  EXPECT_NEAR(masked_ssim(a.data(), a.data(), mask.data(), w, h), 1.0, 1e-12);
  // A constant shift keeps the structure term at 1: SSIM = luminance term < 1.
  const double shifted = masked_ssim(a.data(), b.data(), mask.data(), w, h);
  EXPECT_LT(shifted, 1.0);
  EXPECT_GT(shifted, 0.8);
  std::vector<float> noise(3 * plane);
  for (float& v : noise) v = u(rng);
  EXPECT_LT(masked_ssim(a.data(), noise.data(), mask.data(), w, h), 0.3);
}

TEST(EvalMetrics, LightErrorOfAConstantDifference) {
  // A difference only in coefficient 0 of each channel is the constant d * Y_0 = d / (2 sqrt(pi)).
  std::vector<float> a(27, 0.5f), b(27, 0.5f);
  for (int c = 0; c < 3; ++c) b[c * 9] += static_cast<float>(c + 1);
  double expected = 0;
  for (int c = 0; c < 3; ++c) expected += std::pow((c + 1) * 0.28209479177387814347, 2) / 3.0;
  EXPECT_NEAR(light_error(a.data(), b.data()), expected, 1e-6 * expected);
}

}  // namespace
}  // namespace facetool
