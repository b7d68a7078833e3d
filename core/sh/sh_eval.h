// Evaluation of SH-expanded functions and RGB lights at a direction.
#pragma once

#include <array>

#include "core/sh/sh_types.h"

namespace facetool::sh {

// f(d) = sum_i f_i Y_i(d) for a unit direction d.
double sh_eval(const ShCoeffs& f, const Vec3& d);
// The RGB radiance L(d) of a 27-coefficient light (channel-major).
std::array<double, 3> light_eval(const RgbLight& light, const Vec3& d);

}  // namespace facetool::sh
