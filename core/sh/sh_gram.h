// The 9x9 Gram matrix of the SH basis over the 64,000 illumination-loss directions (for E_L).
#pragma once

#include <array>

namespace facetool::sh {

// G[i][j] = 1/M sum_m Y_i(w_m) Y_j(w_m) over the M = kIlluminationSampleCount Fibonacci
// directions (sphere_samples.h), computed once in double precision. The mean squared difference
// of two lights over those directions is d^T G d with d their coefficient difference.
const std::array<std::array<double, 9>, 9>& illumination_gram_matrix();

}  // namespace facetool::sh
