// Tests of making a light non-negative: unchanged when already so, else projected max(0, L).
#include <gtest/gtest.h>

#include <cmath>

#include "core/sh/light_clamp.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sh_eval.h"
#include "sphere_quadrature.h"

namespace facetool::sh {
namespace {

TEST(LightClamp, NonNegativeLightIsUnchanged) {
  ShCoeffs c{};
  c[0] = 2.0;
  c[2] = 0.5;  // 2 Y_0 + 0.5 Y_1^0 >= 0.564 - 0.244 > 0 everywhere
  const ShCoeffs out = clamp_nonnegative(c);
  for (int i = 0; i < kCoeffCount; ++i) EXPECT_EQ(out[i], c[i]);
}

TEST(LightClamp, NegativeLightBecomesProjectionOfItsPositivePart) {
  ShCoeffs c{};
  c[0] = 0.5;
  c[3] = 1.0;
  c[8] = 0.4;  // strongly negative towards -x
  ASSERT_LT(min_radiance(c), -0.2);
  const ShCoeffs out = clamp_nonnegative(c);
  // Reference by product quadrature on a fine grid (the kink is not aligned, so only ~1e-4).
  for (int i = 0; i < kCoeffCount; ++i) {
    const double q = testing::integrate_sphere(
        [&](const Vec3& w) { return std::fmax(0.0, sh_eval(c, w)) * sh_basis(w)[i]; }, 200, 400);
    EXPECT_NEAR(out[i], q, 2e-4) << "coefficient " << i;
  }
  EXPECT_GT(min_radiance(out), min_radiance(c) * 0.5);
  RgbLight rgb{};
  set_light_channel(rgb, 1, c);
  const RgbLight rgb_out = clamp_light_nonnegative(rgb);
  for (int i = 0; i < kCoeffCount; ++i) {
    EXPECT_EQ(rgb_out[i], 0.0);
    EXPECT_EQ(rgb_out[kCoeffCount + i], out[i]);
  }
}

}  // namespace
}  // namespace facetool::sh
