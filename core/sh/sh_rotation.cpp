// SH rotation matrices: Z_alpha, the fixed X(+-90 deg) matrices, and their ZYZ composition.
#include "core/sh/sh_rotation.h"

#include <cmath>

#include "core/sh/clamped_cosine.h"
#include "core/util/error.h"

namespace facetool::sh {
namespace {

ShMatrix zero_matrix() { return ShMatrix{}; }

Mat3 mat3_multiply(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

Mat3 rz(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3{{{c, -s, 0.0}, {s, c, 0.0}, {0.0, 0.0, 1.0}}};
}

Mat3 ry(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return Mat3{{{c, 0.0, s}, {0.0, 1.0, 0.0}, {-s, 0.0, c}}};
}

}  // namespace

// Derivation: substitute R w into each basis polynomial. For Rz(alpha),
// x' = x c - y s, y' = x s + y c, z' = z gives e.g. x'y' = xy cos 2a + (x^2 - y^2) sin 2a / 2,
// hence Y_4(Rw) = cos 2a Y_4 + sin 2a Y_8. (Same entries as the paper, 0-based.)
ShMatrix sh_rotation_z(double alpha) {
  const double c1 = std::cos(alpha), s1 = std::sin(alpha);
  const double c2 = std::cos(2.0 * alpha), s2 = std::sin(2.0 * alpha);
  ShMatrix m = zero_matrix();
  m[0][0] = 1.0;
  m[1][1] = c1;  m[1][3] = s1;
  m[2][2] = 1.0;
  m[3][1] = -s1; m[3][3] = c1;
  m[4][4] = c2;  m[4][8] = s2;
  m[5][5] = c1;  m[5][7] = s1;
  m[6][6] = 1.0;
  m[7][5] = -s1; m[7][7] = c1;
  m[8][4] = -s2; m[8][8] = c2;
  return m;
}

// Rx(+90): (x, y, z) -> (x, -z, y). With Y_6 = k(3z^2 - 1), Y_8 = sqrt(3) k (x^2 - y^2) on the
// unit sphere: 3y^2 - 1 = -(3z^2 - 1)/2 - 3(x^2 - y^2)/2 and x^2 - z^2 = -(3z^2 - 1)/2 +
// (x^2 - y^2)/2, which give rows 6 and 8. (Same entries as the paper, 0-based.)
ShMatrix sh_rotation_x_plus90() {
  const double h = std::sqrt(3.0) / 2.0;
  ShMatrix m = zero_matrix();
  m[0][0] = 1.0;
  m[1][2] = -1.0;
  m[2][1] = 1.0;
  m[3][3] = 1.0;
  m[4][7] = -1.0;
  m[5][5] = -1.0;
  m[6][6] = -0.5; m[6][8] = -h;
  m[7][4] = 1.0;
  m[8][6] = -h;   m[8][8] = 0.5;
  return m;
}

// Rx(-90): (x, y, z) -> (x, z, -y): the transpose of X(+90).
ShMatrix sh_rotation_x_minus90() {
  const double h = std::sqrt(3.0) / 2.0;
  ShMatrix m = zero_matrix();
  m[0][0] = 1.0;
  m[1][2] = 1.0;
  m[2][1] = -1.0;
  m[3][3] = 1.0;
  m[4][7] = 1.0;
  m[5][5] = -1.0;
  m[6][6] = -0.5; m[6][8] = -h;
  m[7][4] = -1.0;
  m[8][6] = -h;   m[8][8] = 0.5;
  return m;
}

Mat3 rotation_from_zyz(const ZyzAngles& a) {
  return mat3_multiply(rz(a.gamma), mat3_multiply(ry(a.beta), rz(a.alpha)));
}

ZyzAngles zyz_from_rotation(const Mat3& r) {
  const Mat3 rtr = mat3_multiply(
      Mat3{{{r[0][0], r[1][0], r[2][0]}, {r[0][1], r[1][1], r[2][1]}, {r[0][2], r[1][2], r[2][2]}}},
      r);
  double err = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) err = std::fmax(err, std::fabs(rtr[i][j] - (i == j ? 1.0 : 0.0)));
  const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                     r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                     r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  check(std::isfinite(err) && err < 1e-6 && std::fabs(det - 1.0) < 1e-6,
        "SH rotation: the 3x3 matrix is not a rotation (|R^T R - I| = ", err, ", det = ", det,
        "); give an orthonormal matrix with determinant +1");
  ZyzAngles a;
  const double sb = std::sqrt(r[0][2] * r[0][2] + r[1][2] * r[1][2]);
  a.beta = std::atan2(sb, r[2][2]);
  if (sb > 1e-12) {
    a.gamma = std::atan2(r[1][2], r[0][2]);
    a.alpha = std::atan2(r[2][1], -r[2][0]);
  } else if (r[2][2] > 0.0) {  // Rz(alpha + gamma)
    a.gamma = 0.0;
    a.alpha = std::atan2(r[1][0], r[0][0]);
  } else {  // Ry(pi) Rz(alpha) = [[-c, s, 0], [s, c, 0], [0, 0, -1]]
    a.gamma = 0.0;
    a.alpha = std::atan2(r[1][0], r[1][1]);
  }
  return a;
}

ShMatrix multiply(const ShMatrix& a, const ShMatrix& b) {
  ShMatrix c = zero_matrix();
  for (int i = 0; i < kCoeffCount; ++i)
    for (int k = 0; k < kCoeffCount; ++k) {
      if (a[i][k] == 0.0) continue;
      for (int j = 0; j < kCoeffCount; ++j) c[i][j] += a[i][k] * b[k][j];
    }
  return c;
}

ShMatrix sh_rotation(const ZyzAngles& a) {
  ShMatrix m = sh_rotation_z(a.gamma);
  m = multiply(m, sh_rotation_x_minus90());
  m = multiply(m, sh_rotation_z(a.beta));
  m = multiply(m, sh_rotation_x_plus90());
  return multiply(m, sh_rotation_z(a.alpha));
}

ShMatrix sh_rotation(const Mat3& r) { return sh_rotation(zyz_from_rotation(r)); }

ShCoeffs rotate_coeffs(const ShMatrix& m, const ShCoeffs& f) {
  ShCoeffs g{};
  for (int i = 0; i < kCoeffCount; ++i)
    for (int j = 0; j < kCoeffCount; ++j) g[i] += m[i][j] * f[j];
  return g;
}

RgbLight rotate_light(const RgbLight& light, const Mat3& r) {
  const ShMatrix m = sh_rotation(r);
  RgbLight out{};
  for (int c = 0; c < 3; ++c) set_light_channel(out, c, rotate_coeffs(m, light_channel(light, c)));
  return out;
}

ZyzAngles zyz_taking_z_to(const Vec3& n) {
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  check(std::isfinite(len) && len > 0.0, "SH rotation: the target direction (", n[0], ", ", n[1],
        ", ", n[2], ") has no direction; give a finite, nonzero vector");
  ZyzAngles a;
  a.beta = std::atan2(std::sqrt(n[0] * n[0] + n[1] * n[1]), n[2]);  // accurate near the poles
  a.gamma = std::atan2(n[1], n[0]);
  return a;
}

ShCoeffs clamped_cosine_coeffs_by_rotation(const Vec3& n) {
  return rotate_coeffs(sh_rotation(zyz_taking_z_to(n)), clamped_cosine_about_z());
}

}  // namespace facetool::sh
