// Tests of SH rotation: each matrix against M_ij = integral Y_i(Rw) Y_j(w) dw by quadrature.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/sh/clamped_cosine.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sh_eval.h"
#include "core/sh/sh_rotation.h"
#include "core/util/error.h"
#include "sphere_quadrature.h"
#include "core/util/math_constants.h"

namespace facetool::sh {
namespace {


Vec3 mul(const Mat3& r, const Vec3& w) {
  return {r[0][0] * w[0] + r[0][1] * w[1] + r[0][2] * w[2],
          r[1][0] * w[0] + r[1][1] * w[1] + r[1][2] * w[2],
          r[2][0] * w[0] + r[2][1] * w[1] + r[2][2] * w[2]};
}

Mat3 axis_rotation(int axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  if (axis == 0) return Mat3{{{1, 0, 0}, {0, c, -s}, {0, s, c}}};
  if (axis == 1) return Mat3{{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}};
  return Mat3{{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}};
}

// The definition M_ij = integral Y_i(R w) Y_j(w) dw, by quadrature (degree 4: exact).
void expect_matches_definition(const ShMatrix& m, const Mat3& r, const char* what) {
  for (int i = 0; i < kCoeffCount; ++i)
    for (int j = 0; j < kCoeffCount; ++j) {
      const double q = testing::integrate_sphere(
          [&](const Vec3& w) { return sh_basis(mul(r, w))[i] * sh_basis(w)[j]; }, 8, 16);
      EXPECT_NEAR(m[i][j], q, 1e-12) << what << " M_" << i << "," << j;
    }
}

Mat3 random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-kPi, kPi);
  const double a = u(rng), b = std::fabs(u(rng)), c = u(rng);
  return rotation_from_zyz({a, b, c});
}

TEST(ShRotation, FixedMatricesMatchTheirDefinition) {
  expect_matches_definition(sh_rotation_x_plus90(), axis_rotation(0, kPi / 2), "X(+90)");
  expect_matches_definition(sh_rotation_x_minus90(), axis_rotation(0, -kPi / 2), "X(-90)");
  for (double alpha : {0.3, -1.7, 2.9})
    expect_matches_definition(sh_rotation_z(alpha), axis_rotation(2, alpha), "Z(alpha)");
}

TEST(ShRotation, AnyRotationMatchesItsDefinition) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 6; ++trial) {
    const Mat3 r = random_rotation(rng);
    expect_matches_definition(sh_rotation(r), r, "random R");
  }
  // Degenerate Euler angles (beta = 0 and beta = pi) and pure axis rotations.
  expect_matches_definition(sh_rotation(axis_rotation(2, 0.8)), axis_rotation(2, 0.8), "Rz");
  expect_matches_definition(sh_rotation(axis_rotation(1, kPi)), axis_rotation(1, kPi), "Ry(pi)");
  const Mat3 flip = rotation_from_zyz({0.4, kPi, 0.9});
  expect_matches_definition(sh_rotation(flip), flip, "beta = pi");
  expect_matches_definition(sh_rotation(axis_rotation(0, 1.1)), axis_rotation(0, 1.1), "Rx");
}

TEST(ShRotation, EulerAnglesRoundTrip) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const Mat3 r = random_rotation(rng);
    const Mat3 back = rotation_from_zyz(zyz_from_rotation(r));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(back[i][j], r[i][j], 1e-12);
  }
}

TEST(ShRotation, RotatedFunctionSatisfiesGOfRwEqualsFOfW) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ShCoeffs f{};
  for (double& v : f) v = u(rng);
  const Mat3 r = random_rotation(rng);
  const ShCoeffs g = rotate_coeffs(sh_rotation(r), f);
  for (int trial = 0; trial < 20; ++trial) {
    Vec3 w{u(rng), u(rng), u(rng)};
    const double len = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (double& c : w) c /= len;
    EXPECT_NEAR(sh_eval(g, mul(r, w)), sh_eval(f, w), 1e-12);
  }
}

TEST(ShRotation, ZonalShortcutAgreesWithFullRotation) {
  std::mt19937 rng(13);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vec3> normals = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {1e-9, 0, -1}};
  for (int trial = 0; trial < 50; ++trial) normals.push_back({g(rng), g(rng), g(rng)});
  for (const Vec3& n : normals) {
    const ShCoeffs zonal = clamped_cosine_coeffs(n);
    const ShCoeffs rotated = clamped_cosine_coeffs_by_rotation(n);
    for (int k = 0; k < kCoeffCount; ++k)
      EXPECT_NEAR(zonal[k], rotated[k], 1e-12) << "c_" << k << " at (" << n[0] << ", " << n[1]
                                               << ", " << n[2] << ")";
  }
}

TEST(ShRotation, NonRotationIsAnError) {
  const Mat3 mirror{{{1, 0, 0}, {0, 1, 0}, {0, 0, -1}}};
  const Mat3 scaled{{{2, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  EXPECT_THROW(sh_rotation(mirror), Error);
  EXPECT_THROW(sh_rotation(scaled), Error);
}

}  // namespace
}  // namespace facetool::sh
