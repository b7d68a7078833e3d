// E_L: the mean squared difference of two SH lights over 64,000 sphere directions, via their Gram matrix.
#pragma once

#include <array>

#include "core/autograd/variable.h"

namespace facetool::paper_losses {

// E_L = 1/(3 N M) sum_n,c,m (L_pred[n,c] . Y(w_m) - L_target[n,c] . Y(w_m))^2
//     = 1/(3 N) sum_n,c d^T G d (G: sh::illumination_gram_matrix) with d = L_pred[n,c] - L_target[n,c]; lights are [N,27]
// (channel-major). Differentiable in both lights; evaluated on the host in double (27 N values).
ag::Variable light_loss(const ag::Variable& predicted, const ag::Variable& target);

}  // namespace facetool::paper_losses
