// OpenclBackend batch normalisation and per-pixel L2 normalisation.
#include "backends/opencl/opencl_backend.h"

namespace facetool::opencl {

static const char* kBatchNorm = "batchnorm.cl";
static const char* kL2 = "l2_normalize.cl";

void OpenclBackend::batch_norm(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                               const Tensor& running_mean, const Tensor& running_var,
                               const Tensor& save_mean, const Tensor& save_invstd,
                               const Tensor& y, const BatchNormParams& p) {
  const Shape& s = x.shape();
  const int64_t plane = s.h() * s.w();
  run_groups(*this, kBatchNorm, "bn_statistics", s.c(), x, s.n(), s.c(), plane, running_mean,
             running_var, save_mean, save_invstd, p.momentum, p.eps, p.training);
  run_nd(*this, kBatchNorm, "bn_apply", {plane, s.n() * s.c()}, x, save_mean, save_invstd, gamma,
         beta, y, s.c(), plane);
}

void OpenclBackend::batch_norm_backward(const Tensor& x, const Tensor& gamma,
                                        const Tensor& save_mean, const Tensor& save_invstd,
                                        const Tensor& dy, const Tensor* dx, const Tensor* dgamma,
                                        const Tensor* dbeta, const BatchNormParams& p,
                                        bool accumulate) {
  const Shape& s = x.shape();
  const int64_t plane = s.h() * s.w();
  Tensor sums = scratch(2 * s.c());
  // Unwanted outputs get the scratch buffer as a harmless stand-in argument.
  run_groups(*this, kBatchNorm, "bn_backward_reduce", s.c(), x, dy, save_mean, save_invstd, s.n(),
             s.c(), plane, sums, dgamma ? *dgamma : sums, dgamma != nullptr,
             dbeta ? *dbeta : sums, dbeta != nullptr, accumulate);
  if (dx)
    run_nd(*this, kBatchNorm, "bn_backward_dx", {plane, s.n() * s.c()}, x, dy, save_mean,
           save_invstd, gamma, sums, *dx, p.training, accumulate, s.c(), plane, s.n() * plane);
}

void OpenclBackend::l2_normalize(const Tensor& x, float eps, const Tensor& y) {
  const Shape& s = x.shape();
  const int64_t plane = s.h() * s.w();
  run_nd(*this, kL2, "l2_normalize", {plane, s.n()}, x, y, eps, s.c(), plane);
}

void OpenclBackend::l2_normalize_backward(const Tensor& x, float eps, const Tensor& dy,
                                          const Tensor& dx, bool accumulate) {
  const Shape& s = x.shape();
  const int64_t plane = s.h() * s.w();
  run_nd(*this, kL2, "l2_normalize_backward", {plane, s.n()}, x, dy, dx, eps, accumulate, s.c(),
         plane);
}

}  // namespace facetool::opencl
