// Differentiable functions: forward through core/ops, backward recorded as closures.
#include "core/autograd/functions.h"

#include "core/autograd/synced_batch_norm.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ag {

using Targets = std::vector<GradTarget>;

// The gradient tensor of target i, or nullptr when that input needs none.
static const Tensor* out(const Targets& t, size_t i) { return t[i].tensor; }

// All targets of one backward call share one accumulate flag in the op table, so when they
// disagree the overwriting ones are zeroed first and everything accumulates.
static bool unify_accumulate(const Targets& targets) {
  bool any_overwrite = false, any_accumulate = false;
  for (const GradTarget& t : targets) {
    if (!t) continue;
    (t.accumulate ? any_accumulate : any_overwrite) = true;
  }
  if (!any_overwrite) return true;
  if (!any_accumulate) return false;
  for (const GradTarget& t : targets)
    if (t && !t.accumulate) ops::fill(*t.tensor, 0.0f);
  return true;
}

Variable add(const Variable& a, const Variable& b) {
  return make_result(ops::add(a.value(), b.value()), "add", {a, b},
                     [](const Tensor& g, const Targets& t) {
                       if (t[0]) ops::add_backward(g, t[0].tensor, nullptr, t[0].accumulate);
                       if (t[1]) ops::add_backward(g, nullptr, t[1].tensor, t[1].accumulate);
                     });
}

Variable mul(const Variable& a, const Variable& b) {
  Tensor av = a.value(), bv = b.value();
  return make_result(ops::mul(av, bv), "mul", {a, b}, [av, bv](const Tensor& g, const Targets& t) {
    if (t[0]) ops::mul_backward(av, bv, g, t[0].tensor, nullptr, t[0].accumulate);
    if (t[1]) ops::mul_backward(av, bv, g, nullptr, t[1].tensor, t[1].accumulate);
  });
}

Variable scale(const Variable& x, float alpha) {
  return make_result(ops::scale(x.value(), alpha), "scale", {x},
                     [alpha](const Tensor& g, const Targets& t) {
                       ops::scale_backward(g, alpha, *t[0].tensor, t[0].accumulate);
                     });
}

Variable leaky_relu(const Variable& x, float slope) {
  Tensor xv = x.value();
  return make_result(ops::leaky_relu(xv, slope), "leaky_relu", {x},
                     [xv, slope](const Tensor& g, const Targets& t) {
                       ops::leaky_relu_backward(xv, slope, g, *t[0].tensor, t[0].accumulate);
                     });
}

Variable sigmoid(const Variable& x) {
  Tensor y = ops::sigmoid(x.value());
  return make_result(y, "sigmoid", {x}, [y](const Tensor& g, const Targets& t) {
    ops::sigmoid_backward(y, g, *t[0].tensor, t[0].accumulate);
  });
}

Variable concat_channels(const std::vector<Variable>& xs) {
  std::vector<Tensor> values;
  std::vector<int64_t> starts;
  int64_t c0 = 0;
  for (const Variable& x : xs) {
    values.push_back(x.value());
    starts.push_back(c0);
    c0 += x.shape().c();
  }
  return make_result(ops::concat_channels(values), "concat_channels", xs,
                     [starts](const Tensor& g, const Targets& t) {
                       for (size_t i = 0; i < t.size(); ++i) {
                         if (!t[i]) continue;
                         Tensor part = ops::slice_channels(g, starts[i], t[i].tensor->shape().c());
                         if (t[i].accumulate)
                           ops::axpy(1.0f, part, *t[i].tensor);
                         else
                           ops::copy(part, *t[i].tensor);
                       }
                     });
}

Variable slice_channels(const Variable& x, int64_t c0, int64_t count) {
  return make_result(ops::slice_channels(x.value(), c0, count), "slice_channels", {x},
                     [c0](const Tensor& g, const Targets& t) {
                       ops::slice_channels_backward(g, c0, *t[0].tensor, t[0].accumulate);
                     });
}

Variable conv2d(const Variable& x, const Variable& w, const Variable& bias,
                const Conv2dParams& p) {
  Tensor xv = x.value(), wv = w.value();
  const bool has_bias = bias.defined();
  Tensor y = ops::conv2d(xv, wv, has_bias ? &bias.value() : nullptr, p);
  std::vector<Variable> parents{x, w};
  if (has_bias) parents.push_back(bias);
  return make_result(y, "conv2d", parents, [xv, wv, p, has_bias](const Tensor& g, const Targets& t) {
    const bool acc = unify_accumulate(t);
    ops::conv2d_backward(xv, wv, g, out(t, 0), out(t, 1), has_bias ? out(t, 2) : nullptr, p, acc);
  });
}

Variable linear(const Variable& x, const Variable& w, const Variable& bias) {
  Tensor xv = x.value(), wv = w.value();
  const bool has_bias = bias.defined();
  Tensor y = ops::linear(xv, wv, has_bias ? &bias.value() : nullptr);
  std::vector<Variable> parents{x, w};
  if (has_bias) parents.push_back(bias);
  return make_result(y, "linear", parents, [xv, wv, has_bias](const Tensor& g, const Targets& t) {
    const bool acc = unify_accumulate(t);
    ops::linear_backward(xv, wv, g, out(t, 0), out(t, 1), has_bias ? out(t, 2) : nullptr, acc);
  });
}

Variable batch_norm(const Variable& x, const Variable& gamma, const Variable& beta,
                    const Tensor& running_mean, const Tensor& running_var,
                    const BatchNormParams& p) {
  if (p.training && batch_norm_statistics_sum())
    return synced_batch_norm(x, gamma, beta, running_mean, running_var, p,
                             batch_norm_statistics_sum());
  Tensor xv = x.value(), gv = gamma.value();
  ops::BatchNormSaved saved;
  Tensor y = ops::batch_norm(xv, gv, beta.value(), running_mean, running_var, p, &saved);
  return make_result(y, "batch_norm", {x, gamma, beta},
                     [xv, gv, saved, p](const Tensor& g, const Targets& t) {
                       const bool acc = unify_accumulate(t);
                       ops::batch_norm_backward(xv, gv, saved, g, out(t, 0), out(t, 1),
                                                out(t, 2), p, acc);
                     });
}

Variable batch_norm_leaky_relu(const Variable& x, const Variable& gamma, const Variable& beta,
                               const Tensor& running_mean, const Tensor& running_var,
                               const BatchNormParams& p, float slope) {
  // Synchronised statistics (distributed training) and the plain-ops switch compose.
  if ((p.training && batch_norm_statistics_sum()) || !ops::fused_paths_enabled())
    return leaky_relu(batch_norm(x, gamma, beta, running_mean, running_var, p), slope);
  Tensor xv = x.value(), gv = gamma.value();
  ops::BatchNormSaved saved;
  Tensor y = ops::batch_norm_leaky_relu(xv, gv, beta.value(), running_mean, running_var, p,
                                        slope, &saved);
  return make_result(y, "batch_norm_leaky_relu", {x, gamma, beta},
                     [xv, gv, saved, y, p, slope](const Tensor& g, const Targets& t) {
                       const bool acc = unify_accumulate(t);
                       ops::batch_norm_leaky_relu_backward(xv, gv, saved, y, slope, g, out(t, 0),
                                                           out(t, 1), out(t, 2), p, acc);
                     });
}

Variable l2_normalize(const Variable& x, float eps) {
  Tensor xv = x.value();
  return make_result(ops::l2_normalize(xv, eps), "l2_normalize", {x},
                     [xv, eps](const Tensor& g, const Targets& t) {
                       ops::l2_normalize_backward(xv, eps, g, *t[0].tensor, t[0].accumulate);
                     });
}

Variable upsample_bilinear2x(const Variable& x) {
  return make_result(ops::upsample_bilinear2x(x.value()), "upsample_bilinear2x", {x},
                     [](const Tensor& g, const Targets& t) {
                       ops::upsample_bilinear2x_backward(g, *t[0].tensor, t[0].accumulate);
                     });
}

Variable global_avg_pool(const Variable& x) {
  return make_result(ops::global_avg_pool(x.value()), "global_avg_pool", {x},
                     [](const Tensor& g, const Targets& t) {
                       ops::global_avg_pool_backward(g, *t[0].tensor, t[0].accumulate);
                     });
}

Variable sum(const Variable& x) {
  return make_result(ops::sum(x.value()), "sum", {x}, [](const Tensor& g, const Targets& t) {
    ops::sum_backward(g, *t[0].tensor, t[0].accumulate);
  });
}

Variable mean(const Variable& x) {
  return make_result(ops::mean(x.value()), "mean", {x}, [](const Tensor& g, const Targets& t) {
    ops::mean_backward(g, *t[0].tensor, t[0].accumulate);
  });
}

Variable masked_mse(const Variable& pred, const Variable& target, const Tensor& mask) {
  Tensor pv = pred.value(), tv = target.value();
  return make_result(ops::masked_mse(pv, tv, mask), "masked_mse", {pred, target},
                     [pv, tv, mask](const Tensor& g, const Targets& t) {
                       const bool acc = unify_accumulate(t);
                       ops::masked_mse_backward(pv, tv, mask, g, out(t, 0), out(t, 1), acc);
                     });
}

}  // namespace facetool::ag
