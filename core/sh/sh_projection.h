// Projection of a function sampled at (nearly) uniform directions onto the 9 SH coefficients.
#pragma once

#include <functional>
#include <vector>

#include "core/sh/sh_types.h"

namespace facetool::sh {

// f_i = 4 pi / N * sum_s f(d_s) Y_i(d_s): the Monte Carlo form of f_i = integral f Y_i, for N
// uniformly spread directions (e.g. fibonacci_sphere). values[s] belongs to dirs[s].
ShCoeffs project_samples(const std::vector<Vec3>& dirs, const std::vector<double>& values);
// Same, sampling f at each direction.
ShCoeffs project_function(const std::vector<Vec3>& dirs,
                          const std::function<double(const Vec3&)>& f);

}  // namespace facetool::sh
