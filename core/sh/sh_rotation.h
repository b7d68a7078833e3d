// Rotation of degree <= 2 SH coefficients through ZYZ Euler angles (paper appendix A.1).
#pragma once

#include "core/sh/sh_types.h"

namespace facetool::sh {

// Convention: for a rotation R, the rotated function g(R w) = f(w) has coefficients
// g = M(R) f with M_ij = integral Y_i(R w) Y_j(w) dw, equivalently Y_i(R w) = sum_j M_ij Y_j(w).
// M(R1 R2) = M(R1) M(R2), and M(R) is orthogonal and block diagonal per band.

// M for a counter-clockwise rotation by alpha about +Z (paper's Z_alpha).
ShMatrix sh_rotation_z(double alpha);
// M for rotations by +90 and -90 degrees about +X (paper's X_{+90}, X_{-90}; (x, y, z) maps to
// (x, -z, y) and (x, z, -y) respectively).
ShMatrix sh_rotation_x_plus90();
ShMatrix sh_rotation_x_minus90();

// Proper Euler angles: R = Rz(gamma) Ry(beta) Rz(alpha) (extrinsic Z, then Y, then Z), with
// beta in [0, pi].
struct ZyzAngles {
  double alpha = 0.0, beta = 0.0, gamma = 0.0;
};
Mat3 rotation_from_zyz(const ZyzAngles& angles);
// Angles of a rotation matrix (orthonormal, det +1; checked to 1e-6, else facetool::Error).
// At beta = 0 or pi only alpha +- gamma is defined; gamma = 0 is chosen.
ZyzAngles zyz_from_rotation(const Mat3& r);

// M(R) = Z_gamma X_{-90} Z_beta X_{+90} Z_alpha, using Ry(beta) = Rx(-90) Rz(beta) Rx(+90).
ShMatrix sh_rotation(const ZyzAngles& angles);
ShMatrix sh_rotation(const Mat3& r);

ShMatrix multiply(const ShMatrix& a, const ShMatrix& b);
ShCoeffs rotate_coeffs(const ShMatrix& m, const ShCoeffs& f);
// Rotates each channel of a light so that the light arriving from w now arrives from R w.
RgbLight rotate_light(const RgbLight& light, const Mat3& r);

// A rotation taking +Z to the unit vector n (alpha = 0, beta = atan2(|n_xy|, n_z), gamma = atan2(n_y, n_x)).
ZyzAngles zyz_taking_z_to(const Vec3& n);
// Coefficients of max(0, w.n) by rotating clamped_cosine_about_z() with sh_rotation: the long
// route that the zonal shortcut clamped_cosine_coeffs(n) must agree with.
ShCoeffs clamped_cosine_coeffs_by_rotation(const Vec3& n);

}  // namespace facetool::sh
