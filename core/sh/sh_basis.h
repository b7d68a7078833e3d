// The 9 real orthonormal spherical harmonics of degree l <= 2 in the paper's order and sign.
#pragma once

#include "core/sh/sh_types.h"
#include "core/util/math_constants.h"

namespace facetool::sh {

// Order: index i = l(l+1) + m (0-based; the paper's 1-based index is i + 1):
//   0: Y_0^0  = 1 / (2 sqrt(pi))
//   1: Y_1^-1 = sqrt(3 / (4 pi)) y        2: Y_1^0 = sqrt(3 / (4 pi)) z
//   3: Y_1^1  = sqrt(3 / (4 pi)) x
//   4: Y_2^-2 = sqrt(15 / pi) / 2 * x y   5: Y_2^-1 = sqrt(15 / pi) / 2 * y z
//   6: Y_2^0  = sqrt(5 / pi) / 4 * (3 z^2 - 1)
//   7: Y_2^1  = sqrt(15 / pi) / 2 * x z   8: Y_2^2 = sqrt(15 / pi) / 4 * (x^2 - y^2)
// No Condon-Shortley phase: Y_1^1 is +x (the paper's and Ramamoorthi & Hanrahan's sign).
// Normalisation: integral over the sphere of Y_i Y_j = delta_ij (tested by quadrature).
// The constants follow from N_lm = sqrt((2l+1)/(4 pi) (l-|m|)!/(l+|m|)!) times sqrt(2) for
// m != 0, applied to the associated Legendre polynomials P_1^1 = sin, P_2^1 = 3 cos sin,
// P_2^2 = 3 sin^2, P_2^0 = (3 cos^2 - 1) / 2 written in x = sin cos(phi), y = sin sin(phi),
// z = cos (theta the colatitude, phi the azimuth from +x towards +y).
struct ShConstants {
  static constexpr double kPi = facetool::kPi;
  static constexpr double k0 = 0.28209479177387814347;   // 1 / (2 sqrt(pi))
  static constexpr double k1 = 0.48860251190291992159;   // sqrt(3 / (4 pi))
  static constexpr double k2 = 1.09254843059207907054;   // sqrt(15 / pi) / 2
  static constexpr double k20 = 0.31539156525252000603;  // sqrt(5 / pi) / 4
  static constexpr double k22 = 0.54627421529603953527;  // sqrt(15 / pi) / 4
};

constexpr int sh_index(int l, int m) { return l * (l + 1) + m; }
// Degree l of coefficient index i (0 for i = 0, 1 for 1..3, 2 for 4..8).
constexpr int sh_band(int i) { return i == 0 ? 0 : (i < 4 ? 1 : 2); }

// The factor coefficient i takes when its function is seen in a left-right mirror (x -> -x):
// -1 for the functions odd in x (3: x, 4: xy, 7: xz), +1 for the others (tested by quadrature).
constexpr double mirror_x_sign(int i) { return i == 3 || i == 4 || i == 7 ? -1.0 : 1.0; }

// Y_0..Y_8 at the direction d, which must be unit length (not normalised here: on other
// vectors the result is the polynomial extension written above).
ShCoeffs sh_basis(const Vec3& d);
void sh_basis(double x, double y, double z, double out[kCoeffCount]);

// The gradient of each Y_i, as the polynomial above, with respect to (x, y, z).
void sh_basis_gradient(const Vec3& d, double out[kCoeffCount][3]);

}  // namespace facetool::sh
