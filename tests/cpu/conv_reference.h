// Convolution and its gradients by nested loops in double: the reference the cpu tests trust.
#pragma once

#include <cstdint>
#include <vector>

#include "core/tensor/shape.h"

namespace facetool::testing {

// y[n, co, oy, ox] = b[co] + sum x[n, ci, oy*s - pad + ky, ox*s - pad + kx] * w[co, ci, ky, kx]
std::vector<float> conv_reference(const std::vector<float>& x, const Shape& xs,
                                  const std::vector<float>& w, const Shape& ws,
                                  const std::vector<float>& b, int stride, int pad, int64_t ho,
                                  int64_t wo);

// dx of a stride-1 convolution: dx[n, ci, iy, ix] = sum over the outputs that read it.
std::vector<float> conv_dx_reference(const std::vector<float>& dy, const Shape& xs,
                                     const std::vector<float>& w, const Shape& ws, int64_t pad,
                                     int64_t ho, int64_t wo);

// dw of a stride-1 convolution: dw[co, ci, ky, kx] = sum over n, oy, ox of
// dy[n, co, oy, ox] * x[n, ci, oy - pad + ky, ox - pad + kx].
std::vector<float> conv_dw_reference(const std::vector<float>& x, const Shape& xs,
                                     const std::vector<float>& dy, const Shape& ws, int64_t pad,
                                     int64_t ho, int64_t wo);

}  // namespace facetool::testing
