// Op functions: sum and mean reductions, the masked mean-squared error, and Adam.
#include "core/ops/checks.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ops {

using namespace detail;

Tensor sum(const Tensor& x) {
  require_data("sum", "x", x);
  Tensor y = Tensor::empty(x.backend(), Shape{1});
  x.backend().sum(x, y);
  return y;
}

void sum_backward(const Tensor& dy, const Tensor& dx, bool accumulate) {
  require_shape("sum_backward", "dy", dy, Shape{1});
  require_data("sum_backward", "dx", dx);
  require_same_backend("sum_backward", dy, {&dx});
  dy.backend().broadcast_scalar_backward(dy, 1.0f, dx, accumulate);
}

Tensor mean(const Tensor& x) {
  require_data("mean", "x", x);
  Tensor total = sum(x);
  Tensor y = Tensor::empty(x.backend(), Shape{1});
  x.backend().scale(total, 1.0f / static_cast<float>(x.numel()), y);
  return y;
}

void mean_backward(const Tensor& dy, const Tensor& dx, bool accumulate) {
  require_shape("mean_backward", "dy", dy, Shape{1});
  require_data("mean_backward", "dx", dx);
  require_same_backend("mean_backward", dy, {&dx});
  dy.backend().broadcast_scalar_backward(dy, 1.0f / static_cast<float>(dx.numel()), dx,
                                         accumulate);
}

static void check_mse(const char* op, const Tensor& pred, const Tensor& target,
                      const Tensor& mask) {
  require_nchw(op, "pred", pred);
  require_same_shape(op, "pred", pred, "target", target);
  const Shape& s = pred.shape();
  require_shape(op, "mask", mask, Shape{s.n(), 1, s.h(), s.w()});
  require_same_backend(op, pred, {&target, &mask});
}

Tensor masked_mse(const Tensor& pred, const Tensor& target, const Tensor& mask) {
  check_mse("masked_mse", pred, target, mask);
  Tensor loss = Tensor::empty(pred.backend(), Shape{1});
  pred.backend().masked_mse(pred, target, mask, loss);
  return loss;
}

void masked_mse_backward(const Tensor& pred, const Tensor& target, const Tensor& mask,
                         const Tensor& dloss, const Tensor* dpred, const Tensor* dtarget,
                         bool accumulate) {
  check_mse("masked_mse_backward", pred, target, mask);
  require_shape("masked_mse_backward", "dloss", dloss, Shape{1});
  if (dpred) require_same_shape("masked_mse_backward", "pred", pred, "dpred", *dpred);
  if (dtarget) require_same_shape("masked_mse_backward", "target", target, "dtarget", *dtarget);
  require_same_backend("masked_mse_backward", pred, {&dloss, dpred, dtarget});
  if (dpred || dtarget)
    pred.backend().masked_mse_backward(pred, target, mask, dloss, dpred, dtarget, accumulate);
}

void adam_step(const Tensor& param, const Tensor& grad, const Tensor& m, const Tensor& v,
               const AdamParams& p) {
  require_same_shape("adam_step", "param", param, "grad", grad);
  require_same_shape("adam_step", "param", param, "m", m);
  require_same_shape("adam_step", "param", param, "v", v);
  require_same_backend("adam_step", param, {&grad, &m, &v});
  check(p.step >= 1, "adam_step: step counts from 1, got ", p.step);
  param.backend().adam_step(param, grad, m, v, p);
}

void adam_step_all(const std::vector<Backend::AdamTensors>& tensors, const AdamParams& p) {
  if (tensors.empty()) return;
  for (const Backend::AdamTensors& t : tensors) {
    require_same_shape("adam_step_all", "param", t.param, "grad", t.grad);
    require_same_shape("adam_step_all", "param", t.param, "m", t.m);
    require_same_shape("adam_step_all", "param", t.param, "v", t.v);
    require_same_backend("adam_step_all", tensors.front().param, {&t.param, &t.grad, &t.m, &t.v});
  }
  check(p.step >= 1, "adam_step_all: step counts from 1, got ", p.step);
  tensors.front().param.backend().adam_step_all(tensors, p);
}

void launch(const CustomKernel& kernel, const std::string& entry, int64_t work_items,
            const std::vector<KernelArg>& args) {
  check(work_items >= 0, "launch ", kernel.name, ".", entry, ": negative work item count");
  if (work_items == 0) return;
  const Tensor* first = nullptr;
  for (const KernelArg& a : args) {
    if (a.kind != KernelArg::Kind::Tensor) continue;
    check(a.tensor && a.tensor->defined(), "launch ", kernel.name, ".", entry,
          ": an argument is an undefined tensor");
    if (!first) first = a.tensor;
    require_same_backend("launch", *first, {a.tensor});
  }
  check(first != nullptr, "launch ", kernel.name, ".", entry,
        ": needs at least one tensor argument to choose the backend");
  first->backend().launch(kernel, entry, work_items, args);
}

}  // namespace facetool::ops
