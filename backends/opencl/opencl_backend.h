// OpenclBackend: the Backend op table on one OpenCL device (kernels/*.cl plus CLBlast GEMM).
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "backends/opencl/clblast_gemm.h"
#include "backends/opencl/opencl_context.h"
#include "backends/opencl/program_cache.h"
#include "core/backend/backend.h"
#include "core/backend/caching_allocator.h"

namespace facetool::opencl {

// The cl_mem behind a tensor of this backend.
cl_mem device_memory(const Tensor& t);

class OpenclBackend : public Backend {
 public:
  explicit OpenclBackend(const DeviceEntry& device);
  ~OpenclBackend() override;

  std::string name() const override { return "opencl"; }
  std::string device_description() const override;

  // ---- memory (opencl_memory.cpp) ----
  std::shared_ptr<Buffer> allocate(size_t floats) override;
  void upload(const Tensor& dst, const float* src) override;
  void download(const Tensor& src, float* dst) override;
  void synchronize() override;

  // ---- element-wise, activations, channels (ops_elementwise.cpp) ----
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
  void adam_step(const Tensor& param, const Tensor& grad, const Tensor& m, const Tensor& v,
                 const AdamParams& p) override;

  // ---- convolution and fully connected (ops_conv_linear.cpp) ----
  void conv2d(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y,
              const Conv2dParams& p) override;
  void conv2d_backward(const Tensor& x, const Tensor& w, const Tensor& dy, const Tensor* dx,
                       const Tensor* dw, const Tensor* dbias, const Conv2dParams& p,
                       bool accumulate) override;
  void linear(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y) override;
  void linear_backward(const Tensor& x, const Tensor& w, const Tensor& dy, const Tensor* dx,
                       const Tensor* dw, const Tensor* dbias, bool accumulate) override;

  // ---- normalisation (ops_normalization.cpp) ----
  void batch_norm(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                  const Tensor& running_mean, const Tensor& running_var, const Tensor& save_mean,
                  const Tensor& save_invstd, const Tensor& y, const BatchNormParams& p) override;
  void batch_norm_backward(const Tensor& x, const Tensor& gamma, const Tensor& save_mean,
                           const Tensor& save_invstd, const Tensor& dy, const Tensor* dx,
                           const Tensor* dgamma, const Tensor* dbeta, const BatchNormParams& p,
                           bool accumulate) override;
  void l2_normalize(const Tensor& x, float eps, const Tensor& y) override;
  void l2_normalize_backward(const Tensor& x, float eps, const Tensor& dy, const Tensor& dx,
                             bool accumulate) override;

  // ---- resampling, pooling, reductions, losses (ops_resample_reduce.cpp) ----
  void upsample_bilinear2x(const Tensor& x, const Tensor& y) override;
  void upsample_bilinear2x_backward(const Tensor& dy, const Tensor& dx, bool accumulate) override;
  void global_avg_pool(const Tensor& x, const Tensor& y) override;
  void global_avg_pool_backward(const Tensor& dy, const Tensor& dx, bool accumulate) override;
  void sum(const Tensor& x, const Tensor& y) override;
  void broadcast_scalar_backward(const Tensor& dy, float scale, const Tensor& dx,
                                 bool accumulate) override;
  void masked_mse(const Tensor& pred, const Tensor& target, const Tensor& mask,
                  const Tensor& loss) override;
  void masked_mse_backward(const Tensor& pred, const Tensor& target, const Tensor& mask,
                           const Tensor& dloss, const Tensor* dpred, const Tensor* dtarget,
                           bool accumulate) override;

  // ---- plugin kernels (opencl_backend.cpp) ----
  void launch(const CustomKernel& kernel, const std::string& entry, int64_t work_items,
              const std::vector<KernelArg>& args) override;

  // ---- internals shared by the op files ----
  Context& context() { return *context_; }
  ProgramCache& programs() { return *programs_; }
  Gemm& gemm() { return *gemm_; }
  CachingAllocator& allocator() { return *allocator_; }
  // The kernel `entry` of the built-in program kernels/<file>.
  cl_kernel builtin_kernel(const std::string& file, const std::string& entry);
  // A cached device buffer of at least `floats` floats for scratch use within one op.
  Tensor scratch(int64_t floats);
  // Held while a kernel's arguments are set and it is enqueued (cl_kernel is not thread-safe).
  std::mutex& launch_mutex() { return launch_mutex_; }

 private:
  cl_kernel kernel_of(cl_program program, const std::string& program_name,
                      const std::string& entry);

  std::unique_ptr<Context> context_;
  std::unique_ptr<ProgramCache> programs_;
  std::unique_ptr<CachingAllocator> allocator_;
  std::unique_ptr<Gemm> gemm_;
  std::mutex kernels_mutex_;
  std::mutex launch_mutex_;
  std::map<std::pair<cl_program, std::string>, cl_kernel> kernels_;
};

// ---- kernel launching helpers ----

// Sets the arguments of `kernel` in order: cl_mem, int, float (or a Tensor, as its cl_mem).
class KernelArgs {
 public:
  explicit KernelArgs(cl_kernel kernel) : kernel_(kernel) {}
  KernelArgs& mem(cl_mem m);
  KernelArgs& tensor(const Tensor& t) { return mem(device_memory(t)); }
  KernelArgs& i32(int64_t v);
  KernelArgs& f32(float v);

 private:
  cl_kernel kernel_;
  cl_uint index_ = 0;
};

// Enqueues `kernel` over `items` work-items in 1-D groups of `local` (the global size is rounded
// up; kernels ignore the extra items). local == 0 lets the runtime choose and uses items as is.
void enqueue_1d(OpenclBackend& be, cl_kernel kernel, int64_t items, size_t local = 256);
// Enqueues `kernel` over an exact 2-D or 3-D range (size2 == 0: 2-D), local size chosen by the
// runtime; used where the kernel derives channel/row indices from the outer dimensions.
void enqueue_nd(OpenclBackend& be, cl_kernel kernel, int64_t size0, int64_t size1,
                int64_t size2);
// Enqueues exactly `groups` work-groups of `local` items.
void enqueue_groups(OpenclBackend& be, cl_kernel kernel, int64_t groups, size_t local = 256);

// Variadic convenience: run(be, "elementwise.cl", "add", items, a, b, y, n).
inline void set_one(KernelArgs& a, const Tensor& t) { a.tensor(t); }
inline void set_one(KernelArgs& a, cl_mem m) { a.mem(m); }
inline void set_one(KernelArgs& a, int v) { a.i32(v); }
inline void set_one(KernelArgs& a, int64_t v) { a.i32(v); }
inline void set_one(KernelArgs& a, bool v) { a.i32(v ? 1 : 0); }
inline void set_one(KernelArgs& a, float v) { a.f32(v); }

template <typename... Args>
void run_kernel(OpenclBackend& be, const char* file, const char* entry, int64_t items,
                const Args&... args) {
  cl_kernel k = be.builtin_kernel(file, entry);
  std::lock_guard<std::mutex> lock(be.launch_mutex());
  KernelArgs setter(k);
  (set_one(setter, args), ...);
  enqueue_1d(be, k, items);
}

// Over a 2-D (size2 == 0) or 3-D range: run_nd(be, file, entry, {w, h, planes}, args...).
struct Range {
  int64_t size0, size1, size2 = 0;
};
template <typename... Args>
void run_nd(OpenclBackend& be, const char* file, const char* entry, Range range,
            const Args&... args) {
  cl_kernel k = be.builtin_kernel(file, entry);
  std::lock_guard<std::mutex> lock(be.launch_mutex());
  KernelArgs setter(k);
  (set_one(setter, args), ...);
  enqueue_nd(be, k, range.size0, range.size1, range.size2);
}

template <typename... Args>
void run_groups(OpenclBackend& be, const char* file, const char* entry, int64_t groups,
                const Args&... args) {
  cl_kernel k = be.builtin_kernel(file, entry);
  std::lock_guard<std::mutex> lock(be.launch_mutex());
  KernelArgs setter(k);
  (set_one(setter, args), ...);
  enqueue_groups(be, k, groups);
}

}  // namespace facetool::opencl
