// SH coefficients of the clamped cosine max(0, w.n): zonal coefficients and the zonal shortcut.
#pragma once

#include "core/sh/sh_types.h"

namespace facetool::sh {

// Zonal coefficients z_l of max(0, cos theta) about +Z (only Y_0^0, Y_1^0, Y_2^0 are nonzero):
//   z_l = 2 pi * integral_0^1 t * N_l P_l(t) dt
//   z_0 = 2 pi * (1 / (2 sqrt(pi))) * 1/2                = sqrt(pi) / 2
//   z_1 = 2 pi * sqrt(3 / (4 pi)) * 1/3                  = sqrt(pi / 3)
//   z_2 = 2 pi * (sqrt(5 / pi) / 4) * (3/4 - 1/2)        = sqrt(5 pi) / 8
// (these agree with the paper's section 3.1; tested by quadrature).
double clamped_cosine_zonal(int l);
// The 9 coefficients of max(0, w.z): z_0 at index 0, z_1 at 2, z_2 at 6, zero elsewhere.
ShCoeffs clamped_cosine_about_z();

// Per-band factor A_l = sqrt(4 pi / (2l + 1)) * z_l = pi, 2 pi / 3, pi / 4 for l = 0, 1, 2: the
// irradiance E(n) = integral L(w) max(0, w.n) dw of an SH light is sum_i A_l(i) L_i Y_i(n)
// (Ramamoorthi & Hanrahan 2001, the Funk-Hecke theorem).
double cosine_band_factor(int l);

// Coefficients of max(0, w.n) at the unit normal n by the zonal shortcut
// c_k(n) = sqrt(4 pi / (2l + 1)) z_l Y_k(n) = A_l Y_k(n). n is normalised here; a zero or
// non-finite n throws facetool::Error.
ShCoeffs clamped_cosine_coeffs(const Vec3& n);

}  // namespace facetool::sh
