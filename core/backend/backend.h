// Backend: the backend-agnostic op table every compute backend implements (cpu, opencl, ...).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/backend/custom_kernel.h"
#include "core/backend/op_params.h"
#include "core/tensor/tensor.h"

namespace facetool {

// What a fused convolution does after the multiply-adds, per output value of channel c
// (nullptr members are skipped):
//   v  = scale[c] * conv(x, w) + shift[c]     (scale nullptr: 1; shift nullptr: 0)
//   v += residual                              (same shape as the output)
//   y  = activation(v)
//   y2 = leaky_relu(post_scale[c] * y + post_shift[c], post_slope)   (when y2 is given)
// A batch norm in eval mode after the convolution becomes scale/shift (it is folded in); the
// second output is the next layer's batch norm + leaky ReLU (the residual blocks' pre-activation).
struct ConvEpilogue {
  enum class Activation { None, LeakyRelu, Sigmoid };
  const Tensor* scale = nullptr;     // [Co]
  const Tensor* shift = nullptr;     // [Co]
  const Tensor* residual = nullptr;  // [N, Co, Ho, Wo]
  Activation activation = Activation::None;
  float slope = 0.0f;                // of Activation::LeakyRelu
  const Tensor* y2 = nullptr;        // [N, Co, Ho, Wo]
  const Tensor* post_scale = nullptr;  // [Co], required with y2
  const Tensor* post_shift = nullptr;  // [Co], required with y2
  float post_slope = 0.0f;
};

// Every method below receives tensors already checked by core/ops (shapes agree, all tensors
// live on this backend, nothing is empty), so an implementation only computes.
//
// Conventions for backward methods: a gradient output passed as nullptr is not wanted and must
// not be computed. When `accumulate` is true the computed gradient is added to the tensor's
// current contents; when false it overwrites them.
class Backend {
 public:
  virtual ~Backend() = default;

  // Registry name ("cpu", "opencl") and a human description of the device it runs on.
  virtual std::string name() const = 0;
  virtual std::string device_description() const = 0;

  // ---- memory ----
  virtual std::shared_ptr<Buffer> allocate(size_t floats) = 0;
  virtual void upload(const Tensor& dst, const float* src) = 0;
  virtual void download(const Tensor& src, float* dst) = 0;
  // Waits until all queued work has finished (a no-op for synchronous backends).
  virtual void synchronize() {}

  // ---- element-wise and data movement ----
  virtual void fill(const Tensor& t, float value) = 0;
  virtual void copy(const Tensor& src, const Tensor& dst) = 0;
  // y[n, dst_c0 + c, :, :] (+)= x[n, src_c0 + c, :, :] for c < count; x and y share N, H, W.
  virtual void copy_channels(const Tensor& x, int64_t src_c0, const Tensor& y, int64_t dst_c0,
                             int64_t count, bool accumulate) = 0;
  // y = a + b, y = a * b, y = alpha * x (element-wise, equal shapes).
  virtual void add(const Tensor& a, const Tensor& b, const Tensor& y) = 0;
  virtual void mul(const Tensor& a, const Tensor& b, const Tensor& y) = 0;
  virtual void scale(const Tensor& x, float alpha, const Tensor& y) = 0;
  // y += alpha * x
  virtual void axpy(float alpha, const Tensor& x, const Tensor& y) = 0;
  virtual void mul_backward(const Tensor& a, const Tensor& b, const Tensor& dy, const Tensor* da,
                            const Tensor* db, bool accumulate) = 0;

  // ---- activations ----
  virtual void leaky_relu(const Tensor& x, float slope, const Tensor& y) = 0;
  // dx (+)= dy * (x > 0 ? 1 : slope)
  virtual void leaky_relu_backward(const Tensor& x, float slope, const Tensor& dy,
                                   const Tensor& dx, bool accumulate) = 0;
  virtual void sigmoid(const Tensor& x, const Tensor& y) = 0;
  // dx (+)= dy * y * (1 - y), from the forward output y
  virtual void sigmoid_backward(const Tensor& y, const Tensor& dy, const Tensor& dx,
                                bool accumulate) = 0;

  // ---- convolution and fully connected ----
  // x [N,Ci,H,W], w [Co,Ci,K,K], bias [Co] or nullptr, y [N,Co,Ho,Wo]
  virtual void conv2d(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y,
                      const Conv2dParams& p) = 0;
  virtual void conv2d_backward(const Tensor& x, const Tensor& w, const Tensor& dy,
                               const Tensor* dx, const Tensor* dw, const Tensor* dbias,
                               const Conv2dParams& p, bool accumulate) = 0;
  // x [N,Ci], w [Co,Ci], bias [Co] or nullptr, y [N,Co]: y = x w^T + bias
  virtual void linear(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y) = 0;
  virtual void linear_backward(const Tensor& x, const Tensor& w, const Tensor& dy,
                               const Tensor* dx, const Tensor* dw, const Tensor* dbias,
                               bool accumulate) = 0;

  // ---- normalisation ----
  // x, y [N,C,H,W]; gamma, beta, running_mean, running_var, save_mean, save_invstd [C].
  // Writes into save_mean/save_invstd the statistics it normalised with (batch statistics in
  // training, running ones in eval); training mode also updates the running statistics.
  virtual void batch_norm(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                          const Tensor& running_mean, const Tensor& running_var,
                          const Tensor& save_mean, const Tensor& save_invstd, const Tensor& y,
                          const BatchNormParams& p) = 0;
  // With p.training the gradient flows through the batch statistics; in eval mode they are
  // constants.
  virtual void batch_norm_backward(const Tensor& x, const Tensor& gamma,
                                   const Tensor& save_mean, const Tensor& save_invstd,
                                   const Tensor& dy, const Tensor* dx, const Tensor* dgamma,
                                   const Tensor* dbeta, const BatchNormParams& p,
                                   bool accumulate) = 0;
  // Optional fusions (default false: core/ops composes the ops above instead). With slope > 0:
  // y = leaky_relu(batch_norm(x), slope) in one pass (statistics as batch_norm), and its
  // backward from the forward output y (whose sign is the pre-activation's).
  virtual bool batch_norm_leaky_relu(const Tensor& /*x*/, const Tensor& /*gamma*/,
                                     const Tensor& /*beta*/, const Tensor& /*running_mean*/,
                                     const Tensor& /*running_var*/, const Tensor& /*save_mean*/,
                                     const Tensor& /*save_invstd*/, float /*slope*/,
                                     const Tensor& /*y*/, const BatchNormParams& /*p*/) {
    return false;
  }
  virtual bool batch_norm_leaky_relu_backward(
      const Tensor& /*x*/, const Tensor& /*gamma*/, const Tensor& /*save_mean*/,
      const Tensor& /*save_invstd*/, const Tensor& /*y*/, float /*slope*/, const Tensor& /*dy*/,
      const Tensor* /*dx*/, const Tensor* /*dgamma*/, const Tensor* /*dbeta*/,
      const BatchNormParams& /*p*/, bool /*accumulate*/) {
    return false;
  }
  // y = x / max(||x||_2, eps) over the channels of each pixel; x, y [N,C,H,W].
  virtual void l2_normalize(const Tensor& x, float eps, const Tensor& y) = 0;
  virtual void l2_normalize_backward(const Tensor& x, float eps, const Tensor& dy,
                                     const Tensor& dx, bool accumulate) = 0;

  // ---- resampling and pooling ----
  // Bilinear 2x upsampling, align_corners=False: x [N,C,H,W] -> y [N,C,2H,2W].
  virtual void upsample_bilinear2x(const Tensor& x, const Tensor& y) = 0;
  virtual void upsample_bilinear2x_backward(const Tensor& dy, const Tensor& dx,
                                            bool accumulate) = 0;
  // x [N,C,H,W] -> y [N,C]
  virtual void global_avg_pool(const Tensor& x, const Tensor& y) = 0;
  virtual void global_avg_pool_backward(const Tensor& dy, const Tensor& dx, bool accumulate) = 0;

  // ---- reductions and losses (outputs are one-element tensors of shape [1]) ----
  virtual void sum(const Tensor& x, const Tensor& y) = 0;
  // dx (+)= dy[0] * scale
  virtual void broadcast_scalar_backward(const Tensor& dy, float scale, const Tensor& dx,
                                         bool accumulate) = 0;
  // pred, target [N,C,H,W], mask [N,1,H,W]:
  // loss = sum(mask * (pred - target)^2) / (C * sum(mask)), 0 when the mask is empty.
  virtual void masked_mse(const Tensor& pred, const Tensor& target, const Tensor& mask,
                          const Tensor& loss) = 0;
  virtual void masked_mse_backward(const Tensor& pred, const Tensor& target, const Tensor& mask,
                                   const Tensor& dloss, const Tensor* dpred,
                                   const Tensor* dtarget, bool accumulate) = 0;

  // ---- optimiser ----
  // One Adam update of `param` in place from `grad`, with moment buffers m and v.
  virtual void adam_step(const Tensor& param, const Tensor& grad, const Tensor& m,
                         const Tensor& v, const AdamParams& p) = 0;
  // The same update for many parameters at once (the optimiser's whole step): by default one
  // adam_step each; a backend may run them as one parallel loop. Same values either way.
  struct AdamTensors {
    Tensor param, grad, m, v;
  };
  virtual void adam_step_all(const std::vector<AdamTensors>& tensors, const AdamParams& p) {
    for (const AdamTensors& t : tensors) adam_step(t.param, t.grad, t.m, t.v, p);
  }

  // ---- fused inference ops (optional) ----
  // A backend that implements these returns true; the default returns false and core/ops
  // computes the same result from the plain ops above (the reference the fused code is tested
  // against). Forward only: nothing here is differentiated.
  // y = the convolution of x and w (no bias: the epilogue's shift) followed by `e`.
  virtual bool conv2d_fused(const Tensor& /*x*/, const Tensor& /*w*/, const Tensor& /*y*/,
                            const Conv2dParams& /*p*/, const ConvEpilogue& /*e*/) {
    return false;
  }
  // y = leaky_relu(scale[c] * x + shift[c], slope): an eval-mode batch norm and its activation.
  virtual bool channel_affine_leaky_relu(const Tensor& /*x*/, const Tensor& /*scale*/,
                                         const Tensor& /*shift*/, float /*slope*/,
                                         const Tensor& /*y*/) {
    return false;
  }

  // How many images of a `batch` a network's fused forward should run at a time when one
  // image's widest activation takes `bytes_per_image` (so that a chunk's activations can stay in
  // cache between layers); in [1, batch]. The default: the whole batch.
  virtual int64_t fused_batch_chunk(int64_t /*bytes_per_image*/, int64_t batch) { return batch < 1 ? 1 : batch; }
  // Runs the independent branches of a network's fused forward on `batch` images (each a
  // sequence of ops that reads tensors made before and writes tensors of its own). The default:
  // one after the other. The cpu backend runs them at once, each on a thread of its own, where
  // the batch is too small to give every thread work inside each layer (cpu_conv_fused.cpp).
  virtual void run_branches(int64_t /*batch*/, const std::vector<std::function<void()>>& branches) {
    for (const std::function<void()>& branch : branches) branch();
  }

  // ---- plugin kernels ----
  // Runs `entry` of `kernel` over `work_items` items with `args` (see custom_kernel.h).
  virtual void launch(const CustomKernel& kernel, const std::string& entry, int64_t work_items,
                      const std::vector<KernelArg>& args) = 0;
};

}  // namespace facetool
