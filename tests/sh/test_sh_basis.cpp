// Tests of the SH basis: constants against their formulas, orthonormality by quadrature.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sh/sh_basis.h"
#include "sphere_quadrature.h"
#include "core/util/math_constants.h"

namespace facetool::sh {
namespace {


TEST(ShBasis, ConstantsMatchTheirFormulas) {
  EXPECT_NEAR(ShConstants::k0, 1.0 / (2.0 * std::sqrt(kPi)), 1e-15);
  EXPECT_NEAR(ShConstants::k1, std::sqrt(3.0 / (4.0 * kPi)), 1e-15);
  EXPECT_NEAR(ShConstants::k2, std::sqrt(15.0 / kPi) / 2.0, 1e-15);
  EXPECT_NEAR(ShConstants::k20, std::sqrt(5.0 / kPi) / 4.0, 1e-15);
  EXPECT_NEAR(ShConstants::k22, std::sqrt(15.0 / kPi) / 4.0, 1e-15);
}

TEST(ShBasis, IsOrthonormalByQuadrature) {
  for (int i = 0; i < kCoeffCount; ++i)
    for (int j = 0; j < kCoeffCount; ++j) {
      const double integral = testing::integrate_sphere(
          [&](const Vec3& w) { return sh_basis(w)[i] * sh_basis(w)[j]; }, 8, 16);
      EXPECT_NEAR(integral, i == j ? 1.0 : 0.0, 1e-12) << "Y_" << i << " Y_" << j;
    }
}

TEST(ShBasis, OrderAndSignFollowThePaper) {
  // Y_1^1 is +x, Y_1^-1 is +y, Y_1^0 is +z (no Condon-Shortley phase).
  const ShCoeffs px = sh_basis(Vec3{1.0, 0.0, 0.0});
  const ShCoeffs py = sh_basis(Vec3{0.0, 1.0, 0.0});
  const ShCoeffs pz = sh_basis(Vec3{0.0, 0.0, 1.0});
  EXPECT_GT(px[3], 0.0);
  EXPECT_GT(py[1], 0.0);
  EXPECT_GT(pz[2], 0.0);
  EXPECT_EQ(sh_index(2, -2), 4);
  EXPECT_EQ(sh_index(2, 2), 8);
  EXPECT_EQ(sh_band(3), 1);
  EXPECT_EQ(sh_band(4), 2);
}

TEST(ShBasis, GradientMatchesFiniteDifferences) {
  const Vec3 p{0.3, -0.5, 0.7};
  double grad[kCoeffCount][3];
  sh_basis_gradient(p, grad);
  const double h = 1e-6;
  for (int a = 0; a < 3; ++a) {
    Vec3 plus = p, minus = p;
    plus[a] += h;
    minus[a] -= h;
    const ShCoeffs yp = sh_basis(plus), ym = sh_basis(minus);
    for (int i = 0; i < kCoeffCount; ++i)
      EXPECT_NEAR(grad[i][a], (yp[i] - ym[i]) / (2.0 * h), 1e-8) << "Y_" << i << " axis " << a;
  }
}

}  // namespace
}  // namespace facetool::sh
