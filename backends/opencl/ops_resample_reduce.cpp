// OpenclBackend upsampling, pooling, whole-tensor sums and the masked MSE loss.
#include <algorithm>

#include "backends/opencl/opencl_backend.h"

namespace facetool::opencl {
namespace {

const char* kResample = "resample.cl";
const char* kReductions = "reductions.cl";
const char* kLosses = "losses.cl";
constexpr int64_t kGroupSize = 256;

// Work-groups for a two-stage reduction over n items: enough to keep every compute unit busy,
// few enough for the final single-group pass. Fixed for a given n, so results are deterministic.
int64_t reduction_groups(int64_t n) {
  return std::clamp<int64_t>((n + kGroupSize * 16 - 1) / (kGroupSize * 16), 1, 64);
}

}  // namespace

void OpenclBackend::upsample_bilinear2x(const Tensor& x, const Tensor& y) {
  const Shape& s = x.shape();
  run_nd(*this, kResample, "upsample_bilinear2x", {2 * s.w(), 2 * s.h(), s.n() * s.c()}, x, y,
         s.h(), s.w());
}

void OpenclBackend::upsample_bilinear2x_backward(const Tensor& dy, const Tensor& dx,
                                                 bool accumulate) {
  const Shape& s = dx.shape();
  run_nd(*this, kResample, "upsample_bilinear2x_backward", {s.w(), s.h(), s.n() * s.c()}, dy, dx,
         s.h(), s.w(), accumulate);
}

void OpenclBackend::global_avg_pool(const Tensor& x, const Tensor& y) {
  const Shape& s = x.shape();
  run_groups(*this, kResample, "global_avg_pool", s.n() * s.c(), x, y, s.h() * s.w());
}

void OpenclBackend::global_avg_pool_backward(const Tensor& dy, const Tensor& dx,
                                             bool accumulate) {
  const Shape& s = dx.shape();
  run_nd(*this, kResample, "global_avg_pool_backward", {s.h() * s.w(), s.n() * s.c()}, dy, dx,
         s.h() * s.w(), accumulate);
}

void OpenclBackend::sum(const Tensor& x, const Tensor& y) {
  const int64_t groups = reduction_groups(x.numel());
  Tensor partials = scratch(groups);
  run_groups(*this, kReductions, "sum_partials", groups, x, partials, x.numel());
  run_groups(*this, kReductions, "sum_final", 1, partials, groups, y, 1.0f);
}

void OpenclBackend::broadcast_scalar_backward(const Tensor& dy, float scale, const Tensor& dx,
                                              bool accumulate) {
  run_kernel(*this, "elementwise.cl", "broadcast_scalar", dx.numel(), dy, scale, dx, accumulate,
             dx.numel());
}

void OpenclBackend::masked_mse(const Tensor& pred, const Tensor& target, const Tensor& mask,
                               const Tensor& loss) {
  const Shape& s = pred.shape();
  const int64_t groups = reduction_groups(pred.numel());
  Tensor partials = scratch(2 * groups);
  Tensor mask_sum = scratch(1);
  run_groups(*this, kLosses, "masked_mse_partials", groups, pred, target, mask, partials, s.c(),
             s.h() * s.w(), pred.numel(), mask.numel());
  run_groups(*this, kLosses, "masked_mse_final", 1, partials, groups, s.c(), loss, mask_sum);
}

void OpenclBackend::masked_mse_backward(const Tensor& pred, const Tensor& target,
                                        const Tensor& mask, const Tensor& dloss,
                                        const Tensor* dpred, const Tensor* dtarget,
                                        bool accumulate) {
  const Shape& s = pred.shape();
  const int64_t groups = reduction_groups(mask.numel());
  Tensor partials = scratch(groups);
  Tensor mask_sum = scratch(1);
  run_groups(*this, kReductions, "sum_partials", groups, mask, partials, mask.numel());
  run_groups(*this, kReductions, "sum_final", 1, partials, groups, mask_sum, 1.0f);
  run_nd(*this, kLosses, "masked_mse_backward", {s.h() * s.w(), s.n() * s.c()}, pred, target,
         mask, dloss, mask_sum, dpred ? *dpred : mask_sum, dpred != nullptr,
         dtarget ? *dtarget : mask_sum, dtarget != nullptr, accumulate, s.c(), s.h() * s.w());
}

}  // namespace facetool::opencl
