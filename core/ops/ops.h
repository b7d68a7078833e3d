// The op interface: checked, backend-agnostic forward and backward functions on tensors.
#pragma once

#include <vector>

#include "core/backend/backend.h"

// Each forward allocates its output on the inputs' backend; each backward writes the gradients
// it is given (nullptr = not wanted), overwriting them or, with accumulate, adding to them.
// All functions check shapes and backends first and throw facetool::Error naming the op and the
// shapes involved. None of them records anything for autograd: see core/autograd.
namespace facetool::ops {

// ---- memory ----
void fill(const Tensor& t, float value);
void copy(const Tensor& src, const Tensor& dst);

// ---- element-wise ----
Tensor add(const Tensor& a, const Tensor& b);
void add_backward(const Tensor& dy, const Tensor* da, const Tensor* db, bool accumulate);
Tensor mul(const Tensor& a, const Tensor& b);
void mul_backward(const Tensor& a, const Tensor& b, const Tensor& dy, const Tensor* da,
                  const Tensor* db, bool accumulate);
Tensor scale(const Tensor& x, float alpha);
void scale_backward(const Tensor& dy, float alpha, const Tensor& dx, bool accumulate);
void axpy(float alpha, const Tensor& x, const Tensor& y);  // y += alpha * x

// ---- activations ----
Tensor leaky_relu(const Tensor& x, float slope);
void leaky_relu_backward(const Tensor& x, float slope, const Tensor& dy, const Tensor& dx,
                         bool accumulate);
Tensor sigmoid(const Tensor& x);
void sigmoid_backward(const Tensor& y, const Tensor& dy, const Tensor& dx, bool accumulate);

// ---- channels ----
Tensor concat_channels(const std::vector<Tensor>& xs);
void concat_channels_backward(const Tensor& dy, const std::vector<const Tensor*>& dxs,
                              bool accumulate);
Tensor slice_channels(const Tensor& x, int64_t c0, int64_t count);
// Writes dy into channels [c0, c0 + count) of dx; without accumulate the other channels of dx
// are set to zero.
void slice_channels_backward(const Tensor& dy, int64_t c0, const Tensor& dx, bool accumulate);

// ---- convolution and fully connected ----
Tensor conv2d(const Tensor& x, const Tensor& w, const Tensor* bias, const Conv2dParams& p);
void conv2d_backward(const Tensor& x, const Tensor& w, const Tensor& dy, const Tensor* dx,
                     const Tensor* dw, const Tensor* dbias, const Conv2dParams& p,
                     bool accumulate);
Tensor linear(const Tensor& x, const Tensor& w, const Tensor* bias);
void linear_backward(const Tensor& x, const Tensor& w, const Tensor& dy, const Tensor* dx,
                     const Tensor* dw, const Tensor* dbias, bool accumulate);

// ---- normalisation ----
struct BatchNormSaved {
  Tensor mean;    // [C] statistics used by the forward pass
  Tensor invstd;  // [C]
};
Tensor batch_norm(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                  const Tensor& running_mean, const Tensor& running_var, const BatchNormParams& p,
                  BatchNormSaved* saved = nullptr);
void batch_norm_backward(const Tensor& x, const Tensor& gamma, const BatchNormSaved& saved,
                         const Tensor& dy, const Tensor* dx, const Tensor* dgamma,
                         const Tensor* dbeta, const BatchNormParams& p, bool accumulate);
// y = leaky_relu(batch_norm(x), slope) (slope > 0), in one pass where the backend fuses them;
// its backward takes the forward output y (the activation's derivative is read from its sign).
Tensor batch_norm_leaky_relu(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                             const Tensor& running_mean, const Tensor& running_var,
                             const BatchNormParams& p, float slope, BatchNormSaved* saved);
void batch_norm_leaky_relu_backward(const Tensor& x, const Tensor& gamma,
                                    const BatchNormSaved& saved, const Tensor& y, float slope,
                                    const Tensor& dy, const Tensor* dx, const Tensor* dgamma,
                                    const Tensor* dbeta, const BatchNormParams& p,
                                    bool accumulate);
Tensor l2_normalize(const Tensor& x, float eps = 1e-12f);
void l2_normalize_backward(const Tensor& x, float eps, const Tensor& dy, const Tensor& dx,
                           bool accumulate);

// ---- resampling and pooling ----
Tensor upsample_bilinear2x(const Tensor& x);
void upsample_bilinear2x_backward(const Tensor& dy, const Tensor& dx, bool accumulate);
Tensor global_avg_pool(const Tensor& x);
void global_avg_pool_backward(const Tensor& dy, const Tensor& dx, bool accumulate);

// ---- reductions and losses (scalar results have shape [1]) ----
Tensor sum(const Tensor& x);
void sum_backward(const Tensor& dy, const Tensor& dx, bool accumulate);
Tensor mean(const Tensor& x);
void mean_backward(const Tensor& dy, const Tensor& dx, bool accumulate);
Tensor masked_mse(const Tensor& pred, const Tensor& target, const Tensor& mask);
void masked_mse_backward(const Tensor& pred, const Tensor& target, const Tensor& mask,
                         const Tensor& dloss, const Tensor* dpred, const Tensor* dtarget,
                         bool accumulate);

// ---- optimiser ----
void adam_step(const Tensor& param, const Tensor& grad, const Tensor& m, const Tensor& v,
               const AdamParams& p);
// adam_step for every entry, fused into one pass where the backend can (all on one backend).
void adam_step_all(const std::vector<Backend::AdamTensors>& tensors, const AdamParams& p);

// ---- fused inference (core/ops/fused_ops.cpp) ----
// Forward-only combinations of the ops above for evaluation. Each runs on the backend's fused
// implementation when it has one and fused paths are enabled, else on the plain reference
// below; the two agree to float rounding (tests/cpu/cpu_fused_test.cpp).
// Fused paths are on unless FACETOOL_PLAIN_OPS=1 is set in the environment.
bool fused_paths_enabled();
void set_fused_paths_enabled(bool enabled);
// Whether `backend` runs the fused ops itself (and would not fall back to the reference).
bool backend_has_fused_ops(Backend& backend);
// y = conv(x, w) followed by the epilogue `e` (see ConvEpilogue in core/backend/backend.h);
// e.y2, when given, must be an allocated tensor of y's shape.
Tensor conv2d_fused(const Tensor& x, const Tensor& w, const Conv2dParams& p,
                    const ConvEpilogue& e);
// The plain reference of conv2d_fused: ops::conv2d, then the epilogue on the host.
Tensor conv2d_fused_reference(const Tensor& x, const Tensor& w, const Conv2dParams& p,
                              const ConvEpilogue& e);
// y = leaky_relu(scale[c] * x + shift[c], slope).
Tensor channel_affine_leaky_relu(const Tensor& x, const Tensor& scale, const Tensor& shift,
                                 float slope);
// The eval-mode batch norm of the output of a convolution with `conv_bias` (nullptr: none)
// as one per-channel affine map: scale = gamma / sqrt(var + eps),
// shift = (conv_bias - mean) * scale + beta.
void fold_batch_norm(const Tensor& gamma, const Tensor& beta, const Tensor& running_mean,
                     const Tensor& running_var, float eps, const Tensor* conv_bias,
                     Tensor& scale, Tensor& shift);

// ---- plugin kernels ----
void launch(const CustomKernel& kernel, const std::string& entry, int64_t work_items,
            const std::vector<KernelArg>& args);

}  // namespace facetool::ops
