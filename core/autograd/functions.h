// Differentiable functions on Variables: each op of core/ops with its backward recorded.
#pragma once

#include <vector>

#include "core/autograd/variable.h"
#include "core/backend/op_params.h"

namespace facetool::ag {

Variable add(const Variable& a, const Variable& b);
Variable mul(const Variable& a, const Variable& b);
Variable scale(const Variable& x, float alpha);
Variable leaky_relu(const Variable& x, float slope);
Variable sigmoid(const Variable& x);
Variable concat_channels(const std::vector<Variable>& xs);
Variable slice_channels(const Variable& x, int64_t c0, int64_t count);
// `bias` may be an undefined Variable (no bias).
Variable conv2d(const Variable& x, const Variable& w, const Variable& bias,
                const Conv2dParams& p = {});
Variable linear(const Variable& x, const Variable& w, const Variable& bias);
// running_mean / running_var are updated in place in training mode (they are state, not
// differentiable inputs).
Variable batch_norm(const Variable& x, const Variable& gamma, const Variable& beta,
                    const Tensor& running_mean, const Tensor& running_var,
                    const BatchNormParams& p);
// leaky_relu(batch_norm(x), slope), fused where the backend can (slope > 0).
Variable batch_norm_leaky_relu(const Variable& x, const Variable& gamma, const Variable& beta,
                               const Tensor& running_mean, const Tensor& running_var,
                               const BatchNormParams& p, float slope);
Variable l2_normalize(const Variable& x, float eps = 1e-12f);
Variable upsample_bilinear2x(const Variable& x);
Variable global_avg_pool(const Variable& x);
Variable sum(const Variable& x);
Variable mean(const Variable& x);
// The mask is data, never differentiated.
Variable masked_mse(const Variable& pred, const Variable& target, const Tensor& mask);

}  // namespace facetool::ag
