// Op functions: batch normalisation and per-pixel L2 normalisation.
#include "core/ops/checks.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ops {

using namespace detail;

static void check_bn_params(const char* op, const Tensor& x, const Tensor& gamma,
                            const Tensor* beta, const Tensor* running_mean,
                            const Tensor* running_var) {
  require_nchw(op, "x", x);
  const Shape per_channel{x.shape().c()};
  require_shape(op, "gamma", gamma, per_channel);
  if (beta) require_shape(op, "beta", *beta, per_channel);
  if (running_mean) require_shape(op, "running_mean", *running_mean, per_channel);
  if (running_var) require_shape(op, "running_var", *running_var, per_channel);
  require_same_backend(op, x, {&gamma, beta, running_mean, running_var});
}

Tensor batch_norm(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                  const Tensor& running_mean, const Tensor& running_var, const BatchNormParams& p,
                  BatchNormSaved* saved) {
  check_bn_params("batch_norm", x, gamma, &beta, &running_mean, &running_var);
  if (p.training)
    check(x.shape().n() * x.shape().h() * x.shape().w() > 1, "batch_norm: training mode needs ",
          "more than one value per channel, got x ", x.shape().str());
  Backend& be = x.backend();
  BatchNormSaved local;
  BatchNormSaved& s = saved ? *saved : local;
  s.mean = Tensor::empty(be, Shape{x.shape().c()});
  s.invstd = Tensor::empty(be, Shape{x.shape().c()});
  Tensor y = Tensor::empty(be, x.shape());
  be.batch_norm(x, gamma, beta, running_mean, running_var, s.mean, s.invstd, y, p);
  return y;
}

void batch_norm_backward(const Tensor& x, const Tensor& gamma, const BatchNormSaved& saved,
                         const Tensor& dy, const Tensor* dx, const Tensor* dgamma,
                         const Tensor* dbeta, const BatchNormParams& p, bool accumulate) {
  check_bn_params("batch_norm_backward", x, gamma, nullptr, &saved.mean, &saved.invstd);
  require_same_shape("batch_norm_backward", "x", x, "dy", dy);
  if (dx) require_same_shape("batch_norm_backward", "x", x, "dx", *dx);
  if (dgamma) require_same_shape("batch_norm_backward", "gamma", gamma, "dgamma", *dgamma);
  if (dbeta) require_same_shape("batch_norm_backward", "gamma", gamma, "dbeta", *dbeta);
  require_same_backend("batch_norm_backward", x, {&dy, dx, dgamma, dbeta});
  if (dx || dgamma || dbeta)
    x.backend().batch_norm_backward(x, gamma, saved.mean, saved.invstd, dy, dx, dgamma, dbeta, p,
                                    accumulate);
}

Tensor batch_norm_leaky_relu(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                             const Tensor& running_mean, const Tensor& running_var,
                             const BatchNormParams& p, float slope, BatchNormSaved* saved) {
  check_bn_params("batch_norm_leaky_relu", x, gamma, &beta, &running_mean, &running_var);
  check(slope > 0.0f, "batch_norm_leaky_relu: the slope must be positive, got ", slope);
  if (p.training)
    check(x.shape().n() * x.shape().h() * x.shape().w() > 1, "batch_norm_leaky_relu: training ",
          "mode needs more than one value per channel, got x ", x.shape().str());
  Backend& be = x.backend();
  BatchNormSaved local;
  BatchNormSaved& s = saved ? *saved : local;
  if (!fused_paths_enabled())
    return leaky_relu(batch_norm(x, gamma, beta, running_mean, running_var, p, &s), slope);
  s.mean = Tensor::empty(be, Shape{x.shape().c()});
  s.invstd = Tensor::empty(be, Shape{x.shape().c()});
  Tensor y = Tensor::empty(be, x.shape());
  if (be.batch_norm_leaky_relu(x, gamma, beta, running_mean, running_var, s.mean, s.invstd, slope,
                               y, p))
    return y;
  return leaky_relu(batch_norm(x, gamma, beta, running_mean, running_var, p, &s), slope);
}

void batch_norm_leaky_relu_backward(const Tensor& x, const Tensor& gamma,
                                    const BatchNormSaved& saved, const Tensor& y, float slope,
                                    const Tensor& dy, const Tensor* dx, const Tensor* dgamma,
                                    const Tensor* dbeta, const BatchNormParams& p,
                                    bool accumulate) {
  check_bn_params("batch_norm_leaky_relu_backward", x, gamma, nullptr, &saved.mean,
                  &saved.invstd);
  check(slope > 0.0f, "batch_norm_leaky_relu_backward: the slope must be positive, got ", slope);
  require_same_shape("batch_norm_leaky_relu_backward", "x", x, "y", y);
  require_same_shape("batch_norm_leaky_relu_backward", "x", x, "dy", dy);
  if (dx) require_same_shape("batch_norm_leaky_relu_backward", "x", x, "dx", *dx);
  if (dgamma) require_same_shape("batch_norm_leaky_relu_backward", "gamma", gamma, "dgamma", *dgamma);
  if (dbeta) require_same_shape("batch_norm_leaky_relu_backward", "gamma", gamma, "dbeta", *dbeta);
  require_same_backend("batch_norm_leaky_relu_backward", x, {&y, &dy, dx, dgamma, dbeta});
  if (!dx && !dgamma && !dbeta) return;
  if (fused_paths_enabled() &&
      x.backend().batch_norm_leaky_relu_backward(x, gamma, saved.mean, saved.invstd, y, slope,
                                                 dy, dx, dgamma, dbeta, p, accumulate))
    return;
  // The plain composition: y's sign is the pre-activation's, so it selects the derivative.
  Tensor dnorm = Tensor::empty(x.backend(), x.shape());
  leaky_relu_backward(y, slope, dy, dnorm, false);
  batch_norm_backward(x, gamma, saved, dnorm, dx, dgamma, dbeta, p, accumulate);
}

Tensor l2_normalize(const Tensor& x, float eps) {
  require_nchw("l2_normalize", "x", x);
  check(eps > 0.0f, "l2_normalize: eps must be positive, got ", eps);
  Tensor y = Tensor::empty(x.backend(), x.shape());
  x.backend().l2_normalize(x, eps, y);
  return y;
}

void l2_normalize_backward(const Tensor& x, float eps, const Tensor& dy, const Tensor& dx,
                           bool accumulate) {
  require_nchw("l2_normalize_backward", "x", x);
  require_same_shape("l2_normalize_backward", "x", x, "dy", dy);
  require_same_shape("l2_normalize_backward", "x", x, "dx", dx);
  require_same_backend("l2_normalize_backward", x, {&dy, &dx});
  x.backend().l2_normalize_backward(x, eps, dy, dx, accumulate);
}

}  // namespace facetool::ops
