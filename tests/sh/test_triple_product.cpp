// Tests of the tripling coefficients and SH product integrals against exact quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/sh/sh_basis.h"
#include "core/sh/sh_eval.h"
#include "core/sh/triple_product.h"
#include "sphere_quadrature.h"
#include "core/util/math_constants.h"

namespace facetool::sh {
namespace {


ShCoeffs random_coeffs(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ShCoeffs c{};
  for (double& v : c) v = u(rng);
  return c;
}

// Degree-6 polynomials: 8 Gauss-Legendre nodes per half and 16 azimuths are exact.
TEST(TripleProduct, EveryCoefficientMatchesQuadrature) {
  const TripleProductTable& t = TripleProductTable::get();
  for (int i = 0; i < kCoeffCount; ++i)
    for (int j = 0; j < kCoeffCount; ++j)
      for (int k = 0; k < kCoeffCount; ++k) {
        const double q = testing::integrate_sphere(
            [&](const Vec3& w) {
              const ShCoeffs y = sh_basis(w);
              return y[i] * y[j] * y[k];
            },
            8, 16);
        EXPECT_NEAR(t(i, j, k), q, 1e-12) << "T_" << i << j << k << " (0-based)";
      }
  EXPECT_EQ(t.sorted_entries().size(), 25u);
  EXPECT_EQ(t.all_entries().size(), 83u);
}

TEST(TripleProduct, PaperMisprintIsCorrected) {
  // The paper prints T_668 = sqrt(15/pi)/14 (1-based); that value belongs to T_568.
  const TripleProductTable& t = TripleProductTable::get();
  EXPECT_EQ(t(5, 5, 7), 0.0);
  EXPECT_NEAR(t(4, 5, 7), std::sqrt(15.0 / kPi) / 14.0, 1e-15);
  EXPECT_NEAR(t(5, 5, 6), std::sqrt(5.0 / kPi) / 14.0, 1e-15);  // paper's T_667
}

TEST(TripleProduct, ProductIntegralsMatchQuadrature) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    const ShCoeffs f = random_coeffs(rng), g = random_coeffs(rng), h = random_coeffs(rng);
    const double two = testing::integrate_sphere(
        [&](const Vec3& w) { return sh_eval(f, w) * sh_eval(g, w); }, 8, 16);
    EXPECT_NEAR(integrate_product(f, g), two, 1e-12);
    const double three = testing::integrate_sphere(
        [&](const Vec3& w) { return sh_eval(h, w) * sh_eval(f, w) * sh_eval(g, w); }, 8, 16);
    EXPECT_NEAR(integrate_triple(h, f, g), three, 1e-12);
    const ShCoeffs e = product_coeffs(f, g);
    for (int i = 0; i < kCoeffCount; ++i) {
      const double ei = testing::integrate_sphere(
          [&](const Vec3& w) { return sh_basis(w)[i] * sh_eval(f, w) * sh_eval(g, w); }, 8, 16);
      EXPECT_NEAR(e[i], ei, 1e-12) << "e_" << i;
    }
  }
}

}  // namespace
}  // namespace facetool::sh
