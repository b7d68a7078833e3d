// Tests of the clamped-cosine zonal coefficients and the zonal shortcut against quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/sh/clamped_cosine.h"
#include "core/sh/sh_basis.h"
#include "core/util/error.h"
#include "sphere_quadrature.h"
#include "core/util/math_constants.h"

namespace facetool::sh {
namespace {


double clamped_dot(const Vec3& w, const Vec3& n) {
  return std::fmax(0.0, w[0] * n[0] + w[1] * n[1] + w[2] * n[2]);
}

TEST(ClampedCosine, ZonalCoefficientsMatchThePaperAndQuadrature) {
  EXPECT_NEAR(clamped_cosine_zonal(0), std::sqrt(kPi) / 2.0, 1e-15);
  EXPECT_NEAR(clamped_cosine_zonal(1), std::sqrt(kPi / 3.0), 1e-15);
  EXPECT_NEAR(clamped_cosine_zonal(2), std::sqrt(5.0 * kPi) / 8.0, 1e-15);
  const Vec3 z{0.0, 0.0, 1.0};
  const ShCoeffs about_z = clamped_cosine_about_z();
  for (int i = 0; i < kCoeffCount; ++i) {
    const double q = testing::integrate_sphere(
        [&](const Vec3& w) { return clamped_dot(w, z) * sh_basis(w)[i]; }, 8, 16, z);
    EXPECT_NEAR(about_z[i], q, 1e-12) << "coefficient " << i;
  }
}

TEST(ClampedCosine, BandFactorsArePiTwoPiThirdsPiQuarter) {
  EXPECT_NEAR(cosine_band_factor(0), kPi, 1e-14);
  EXPECT_NEAR(cosine_band_factor(1), 2.0 * kPi / 3.0, 1e-14);
  EXPECT_NEAR(cosine_band_factor(2), kPi / 4.0, 1e-14);
}

TEST(ClampedCosine, ZonalShortcutMatchesQuadratureAtRandomNormals) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 raw{g(rng), g(rng), g(rng)};
    const double len = std::sqrt(raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2]);
    const Vec3 n{raw[0] / len, raw[1] / len, raw[2] / len};
    const ShCoeffs c = clamped_cosine_coeffs(raw);  // normalised inside
    for (int k = 0; k < kCoeffCount; ++k) {
      const double q = testing::integrate_sphere(
          [&](const Vec3& w) { return clamped_dot(w, n) * sh_basis(w)[k]; }, 8, 16, n);
      EXPECT_NEAR(c[k], q, 1e-12) << "c_" << k << " trial " << trial;
    }
  }
}

TEST(ClampedCosine, ZeroOrNanNormalIsAnError) {
  EXPECT_THROW(clamped_cosine_coeffs(Vec3{0.0, 0.0, 0.0}), Error);
  EXPECT_THROW(clamped_cosine_coeffs(Vec3{std::nan(""), 0.0, 1.0}), Error);
  EXPECT_THROW(clamped_cosine_zonal(3), Error);
}

}  // namespace
}  // namespace facetool::sh
