// Recovering SH illumination from SH shading coefficients (paper appendix B).
#pragma once

#include <vector>

#include "core/sh/sh_types.h"

namespace facetool::sh {

// Shading S(n) = integral L(w) max(0, w.n) dw = sum_i S_i Y_i(n) (no albedo, no 1/pi).
// With c_i(n) = A_l Y_i(n) (clamped_cosine.h) the paper's equation sum_i S_i Y_i(n) =
// sum_i L_i c_i(n) = sum_i L_i A_l Y_i(n) holds for every n exactly when S_i = A_l L_i, so
//   L_i = S_i / A_l,  A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4.
// (The renderer's image with v = 1 is then rho / pi * S(n).)
ShCoeffs illumination_from_shading(const ShCoeffs& shading);
RgbLight illumination_from_shading(const RgbLight& shading);
ShCoeffs shading_from_illumination(const ShCoeffs& light);
RgbLight shading_from_illumination(const RgbLight& light);

// The paper's route: the over-determined system sum_i L_i c_i(n_s) = sum_i S_i Y_i(n_s) over
// the directions n_s (the paper uses 64,000), solved in the least-squares sense through the
// 9x9 normal equations. Gives the same L as the per-band division (tested); kept to show it.
ShCoeffs illumination_from_shading_least_squares(const ShCoeffs& shading,
                                                 const std::vector<Vec3>& directions);

}  // namespace facetool::sh
