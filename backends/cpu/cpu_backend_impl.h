// CpuBackend: the reference backend on host memory, multithreaded with parallel_for.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/backend/backend.h"
#include "core/backend/caching_allocator.h"

namespace facetool::cpu {

struct ConvGeometry;  // cpu_im2col.h
struct Epilogue;      // cpu_epilogue.h
enum class ConvAlgorithm;  // cpu_conv_choice.h

class CpuBackend final : public Backend {
 public:
  CpuBackend();

  std::string name() const override { return "cpu"; }
  std::string device_description() const override;

  // memory (cpu_memory.cpp)
  std::shared_ptr<Buffer> allocate(size_t floats) override;
  void upload(const Tensor& dst, const float* src) override;
  void download(const Tensor& src, float* dst) override;

  // element-wise and data movement (cpu_elementwise.cpp)
  void fill(const Tensor& t, float value) override;
  void copy(const Tensor& src, const Tensor& dst) override;
  void copy_channels(const Tensor& x, int64_t src_c0, const Tensor& y, int64_t dst_c0,
                     int64_t count, bool accumulate) override;
  void add(const Tensor& a, const Tensor& b, const Tensor& y) override;
  void mul(const Tensor& a, const Tensor& b, const Tensor& y) override;
  void scale(const Tensor& x, float alpha, const Tensor& y) override;
  void axpy(float alpha, const Tensor& x, const Tensor& y) override;
  void mul_backward(const Tensor& a, const Tensor& b, const Tensor& dy, const Tensor* da,
                    const Tensor* db, bool accumulate) override;
  void leaky_relu(const Tensor& x, float slope, const Tensor& y) override;
  void leaky_relu_backward(const Tensor& x, float slope, const Tensor& dy, const Tensor& dx,
                           bool accumulate) override;
  void sigmoid(const Tensor& x, const Tensor& y) override;
  void sigmoid_backward(const Tensor& y, const Tensor& dy, const Tensor& dx,
                        bool accumulate) override;

  // convolution (cpu_conv.cpp) and fully connected (cpu_linear.cpp)
  void conv2d(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y,
              const Conv2dParams& p) override;
  void conv2d_backward(const Tensor& x, const Tensor& w, const Tensor& dy, const Tensor* dx,
                       const Tensor* dw, const Tensor* dbias, const Conv2dParams& p,
                       bool accumulate) override;
  void linear(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y) override;
  void linear_backward(const Tensor& x, const Tensor& w, const Tensor& dy, const Tensor* dx,
                       const Tensor* dw, const Tensor* dbias, bool accumulate) override;

  // normalisation (cpu_batchnorm.cpp, cpu_l2_normalize.cpp)
  void batch_norm(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                  const Tensor& running_mean, const Tensor& running_var, const Tensor& save_mean,
                  const Tensor& save_invstd, const Tensor& y, const BatchNormParams& p) override;
  void batch_norm_backward(const Tensor& x, const Tensor& gamma, const Tensor& save_mean,
                           const Tensor& save_invstd, const Tensor& dy, const Tensor* dx,
                           const Tensor* dgamma, const Tensor* dbeta, const BatchNormParams& p,
                           bool accumulate) override;
  bool batch_norm_leaky_relu(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                             const Tensor& running_mean, const Tensor& running_var,
                             const Tensor& save_mean, const Tensor& save_invstd, float slope,
                             const Tensor& y, const BatchNormParams& p) override;
  bool batch_norm_leaky_relu_backward(const Tensor& x, const Tensor& gamma,
                                      const Tensor& save_mean, const Tensor& save_invstd,
                                      const Tensor& y, float slope, const Tensor& dy,
                                      const Tensor* dx, const Tensor* dgamma,
                                      const Tensor* dbeta, const BatchNormParams& p,
                                      bool accumulate) override;
  void l2_normalize(const Tensor& x, float eps, const Tensor& y) override;
  void l2_normalize_backward(const Tensor& x, float eps, const Tensor& dy, const Tensor& dx,
                             bool accumulate) override;

  // resampling and pooling (cpu_resample.cpp)
  void upsample_bilinear2x(const Tensor& x, const Tensor& y) override;
  void upsample_bilinear2x_backward(const Tensor& dy, const Tensor& dx,
                                    bool accumulate) override;
  void global_avg_pool(const Tensor& x, const Tensor& y) override;
  void global_avg_pool_backward(const Tensor& dy, const Tensor& dx, bool accumulate) override;

  // reductions and losses (cpu_losses.cpp)
  void sum(const Tensor& x, const Tensor& y) override;
  void broadcast_scalar_backward(const Tensor& dy, float scale, const Tensor& dx,
                                 bool accumulate) override;
  void masked_mse(const Tensor& pred, const Tensor& target, const Tensor& mask,
                  const Tensor& loss) override;
  void masked_mse_backward(const Tensor& pred, const Tensor& target, const Tensor& mask,
                           const Tensor& dloss, const Tensor* dpred, const Tensor* dtarget,
                           bool accumulate) override;

  // optimiser (cpu_adam.cpp)
  void adam_step(const Tensor& param, const Tensor& grad, const Tensor& m, const Tensor& v,
                 const AdamParams& p) override;
  void adam_step_all(const std::vector<AdamTensors>& tensors, const AdamParams& p) override;

  // fused inference (cpu_conv_fused.cpp): the algorithm of cpu_conv_choice.h, epilogue inside
  bool conv2d_fused(const Tensor& x, const Tensor& w, const Tensor& y, const Conv2dParams& p,
                    const ConvEpilogue& e) override;
  bool channel_affine_leaky_relu(const Tensor& x, const Tensor& scale, const Tensor& shift,
                                 float slope, const Tensor& y) override;
  // cpu_conv_choice.h's chosen_fused_chunk: the rule or this machine's measured choice
  int64_t fused_batch_chunk(int64_t bytes_per_image, int64_t batch) override;
  // at once, a thread each, when the batch is under the thread count and the branches fill them
  void run_branches(int64_t batch, const std::vector<std::function<void()>>& branches) override;
  // y = conv(x, w) then the epilogue (nullptr: none) by one given algorithm; false when it does
  // not apply to the shape. For benchmarks and tests that compare the algorithms.
  bool convolve_with(ConvAlgorithm algorithm, const ConvGeometry& g, int64_t batch,
                     int64_t out_channels, const float* x, const float* w, float* y,
                     const Epilogue* epilogue);

  // plugin kernels (cpu_custom_kernel.cpp)
  void launch(const CustomKernel& kernel, const std::string& entry, int64_t work_items,
              const std::vector<KernelArg>& args) override;

  // Scratch memory from the backend's cache, returned when the handle goes away.
  class Scratch {
   public:
    Scratch(CachingAllocator& allocator, size_t floats);
    ~Scratch();
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;
    float* data() const { return data_; }

   private:
    CachingAllocator& allocator_;
    float* data_;
    size_t bytes_;
  };
  Scratch scratch(size_t floats) { return Scratch(*allocator_, floats); }

 private:
  // y (+)= conv(x, w) (+ bias) on raw arrays: Winograd where it applies, else im2col + SGEMM.
  void convolve_any(const ConvGeometry& g, int64_t batch, int64_t out_channels,
                    const float* x, const float* w, const float* bias, float* y,
                    bool accumulate);

  std::shared_ptr<CachingAllocator> allocator_;
};

// Element-wise loops split into chunks of this many items.
constexpr int64_t kElementwiseGrain = 16384;

// Host pointer of a cpu tensor (ops have already checked it lives here).
inline float* ptr(const Tensor& t) { return t.host_data(); }

// out = value, or out += value with accumulate; assignment never reads the old contents.
inline void store(float& out, float value, bool accumulate) {
  if (accumulate)
    out += value;
  else
    out = value;
}

}  // namespace facetool::cpu
