// Tests of recovering illumination from shading: closed form, least squares, quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/sh/illumination_from_shading.h"
#include "core/sh/sh_eval.h"
#include "core/sh/sphere_samples.h"
#include "sphere_quadrature.h"

namespace facetool::sh {
namespace {

ShCoeffs random_coeffs(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ShCoeffs c{};
  for (double& v : c) v = u(rng);
  return c;
}

// S(n) = integral L(w) max(0, w.n) dw by quadrature (kink on the split) must equal the
// expansion of shading_from_illumination(L) at n.
TEST(IlluminationFromShading, ShadingOfALightMatchesQuadrature) {
  const ShCoeffs light = random_coeffs(21);
  const ShCoeffs shading = shading_from_illumination(light);
  for (const Vec3& n : fibonacci_sphere(25)) {
    const double q = testing::integrate_sphere(
        [&](const Vec3& w) {
          return sh_eval(light, w) * std::fmax(0.0, w[0] * n[0] + w[1] * n[1] + w[2] * n[2]);
        },
        8, 16, n);
    EXPECT_NEAR(sh_eval(shading, n), q, 1e-12);
  }
}

TEST(IlluminationFromShading, InvertsShadingAndAgreesWithLeastSquares) {
  const ShCoeffs light = random_coeffs(22);
  const ShCoeffs shading = shading_from_illumination(light);
  const ShCoeffs back = illumination_from_shading(shading);
  const ShCoeffs ls =
      illumination_from_shading_least_squares(shading, fibonacci_sphere(kIlluminationSampleCount));
  for (int i = 0; i < kCoeffCount; ++i) {
    EXPECT_NEAR(back[i], light[i], 1e-14);
    EXPECT_NEAR(ls[i], light[i], 1e-10);
  }
  RgbLight rgb{};
  for (int i = 0; i < kLightCoeffCount; ++i) rgb[i] = 0.1 * i - 1.0;
  const RgbLight rgb_back = illumination_from_shading(shading_from_illumination(rgb));
  for (int i = 0; i < kLightCoeffCount; ++i) EXPECT_NEAR(rgb_back[i], rgb[i], 1e-14);
}

}  // namespace
}  // namespace facetool::sh
