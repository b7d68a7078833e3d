// Op functions for fused inference: convolution + epilogue, batch norm + leaky ReLU, folding.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <atomic>

#include "core/ops/checks.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ops {

using namespace detail;

namespace {

std::atomic<bool>& fused_flag() {
  static std::atomic<bool> flag{[] {
    const char* env = std::getenv("FACETOOL_PLAIN_OPS");
    return !(env && std::strcmp(env, "1") == 0);
  }()};
  return flag;
}

float leaky(float v, float slope) { return v > 0.0f ? v : slope * v; }

void check_epilogue(const Tensor& y_like, const Shape& ys, const ConvEpilogue& e) {
  const Shape per_channel{ys.c()};
  if (e.scale) require_shape("conv2d_fused", "scale", *e.scale, per_channel);
  if (e.shift) require_shape("conv2d_fused", "shift", *e.shift, per_channel);
  if (e.residual) require_shape("conv2d_fused", "residual", *e.residual, ys);
  if (e.y2) {
    require_shape("conv2d_fused", "second output y2", *e.y2, ys);
    check(e.post_scale && e.post_shift, "conv2d_fused: a second output needs post_scale and ",
          "post_shift");
    require_shape("conv2d_fused", "post_scale", *e.post_scale, per_channel);
    require_shape("conv2d_fused", "post_shift", *e.post_shift, per_channel);
  }
  require_same_backend("conv2d_fused", y_like,
                       {e.scale, e.shift, e.residual, e.y2, e.post_scale, e.post_shift});
}

}  // namespace

bool fused_paths_enabled() { return fused_flag().load(); }
void set_fused_paths_enabled(bool enabled) { fused_flag().store(enabled); }

bool backend_has_fused_ops(Backend& backend) {
  // The cpu backend implements both fused ops; other backends run the reference.
  return backend.name() == "cpu";
}

Tensor conv2d_fused_reference(const Tensor& x, const Tensor& w, const Conv2dParams& p,
                              const ConvEpilogue& e) {
  Tensor conv = conv2d(x, w, nullptr, p);
  const Shape ys = conv.shape();
  check_epilogue(x, ys, e);
  std::vector<float> v = conv.to_host();
  const std::vector<float> scale = e.scale ? e.scale->to_host() : std::vector<float>();
  const std::vector<float> shift = e.shift ? e.shift->to_host() : std::vector<float>();
  const std::vector<float> residual = e.residual ? e.residual->to_host() : std::vector<float>();
  const int64_t plane = ys.h() * ys.w();
  for (size_t i = 0; i < v.size(); ++i) {
    const size_t c = static_cast<size_t>((static_cast<int64_t>(i) / plane) % ys.c());
    float value = v[i];
    if (e.scale) value *= scale[c];
    if (e.shift) value += shift[c];
    if (e.residual) value += residual[i];
    switch (e.activation) {
      case ConvEpilogue::Activation::None: break;
      case ConvEpilogue::Activation::LeakyRelu: value = leaky(value, e.slope); break;
      case ConvEpilogue::Activation::Sigmoid: value = 1.0f / (1.0f + std::exp(-value)); break;
    }
    v[i] = value;
  }
  Tensor y = Tensor::from_host(x.backend(), ys, v);
  if (e.y2) {
    const std::vector<float> ps = e.post_scale->to_host(), pt = e.post_shift->to_host();
    for (size_t i = 0; i < v.size(); ++i) {
      const size_t c = static_cast<size_t>((static_cast<int64_t>(i) / plane) % ys.c());
      v[i] = leaky(ps[c] * v[i] + pt[c], e.post_slope);
    }
    e.y2->copy_from_host(v);
  }
  return y;
}

Tensor conv2d_fused(const Tensor& x, const Tensor& w, const Conv2dParams& p,
                    const ConvEpilogue& e) {
  Backend& be = x.backend();
  if (!fused_paths_enabled()) return conv2d_fused_reference(x, w, p, e);
  // The same checks as conv2d (core/ops/conv_ops.cpp), then the epilogue's.
  require_nchw("conv2d_fused", "input x", x);
  require_nchw("conv2d_fused", "weight w", w);
  const Shape& xs = x.shape();
  const Shape& ws = w.shape();
  check(ws.h() == ws.w() && ws.h() % 2 == 1, "conv2d_fused: the kernel must be square with an ",
        "odd size, got weight ", ws.str());
  check(ws.c() == xs.c(), "conv2d_fused: weight ", ws.str(), " expects ", ws.c(),
        " input channels but x ", xs.str(), " has ", xs.c());
  check(p.stride >= 1, "conv2d_fused: stride must be >= 1, got ", p.stride);
  const int pad = p.effective_pad(ws.h());
  check(xs.h() + 2 * pad >= ws.h() && xs.w() + 2 * pad >= ws.w(), "conv2d_fused: input x ",
        xs.str(), " with padding ", pad, " is smaller than the kernel of weight ", ws.str());
  require_same_backend("conv2d_fused", x, {&w});
  const Shape ys{xs.n(), ws.n(), (xs.h() + 2 * pad - ws.h()) / p.stride + 1,
                 (xs.w() + 2 * pad - ws.w()) / p.stride + 1};
  check_epilogue(x, ys, e);
  Tensor y = Tensor::empty(be, ys);
  if (be.conv2d_fused(x, w, y, p, e)) return y;
  return conv2d_fused_reference(x, w, p, e);
}

Tensor channel_affine_leaky_relu(const Tensor& x, const Tensor& scale, const Tensor& shift,
                                 float slope) {
  require_nchw("channel_affine_leaky_relu", "x", x);
  const Shape per_channel{x.shape().c()};
  require_shape("channel_affine_leaky_relu", "scale", scale, per_channel);
  require_shape("channel_affine_leaky_relu", "shift", shift, per_channel);
  require_same_backend("channel_affine_leaky_relu", x, {&scale, &shift});
  Tensor y = Tensor::empty(x.backend(), x.shape());
  if (fused_paths_enabled() &&
      x.backend().channel_affine_leaky_relu(x, scale, shift, slope, y))
    return y;
  std::vector<float> v = x.to_host();
  const std::vector<float> s = scale.to_host(), t = shift.to_host();
  const int64_t plane = x.shape().h() * x.shape().w();
  for (size_t i = 0; i < v.size(); ++i) {
    const size_t c = static_cast<size_t>((static_cast<int64_t>(i) / plane) % x.shape().c());
    v[i] = leaky(s[c] * v[i] + t[c], slope);
  }
  y.copy_from_host(v);
  return y;
}

void fold_batch_norm(const Tensor& gamma, const Tensor& beta, const Tensor& running_mean,
                     const Tensor& running_var, float eps, const Tensor* conv_bias,
                     Tensor& scale, Tensor& shift) {
  require_data("fold_batch_norm", "gamma", gamma);
  const Shape per_channel{gamma.shape().numel()};
  require_shape("fold_batch_norm", "gamma", gamma, per_channel);
  require_shape("fold_batch_norm", "beta", beta, per_channel);
  require_shape("fold_batch_norm", "running_mean", running_mean, per_channel);
  require_shape("fold_batch_norm", "running_var", running_var, per_channel);
  if (conv_bias) require_shape("fold_batch_norm", "conv_bias", *conv_bias, per_channel);
  require_same_backend("fold_batch_norm", gamma, {&beta, &running_mean, &running_var, conv_bias});
  const std::vector<float> g = gamma.to_host(), b = beta.to_host(), m = running_mean.to_host(),
                           var = running_var.to_host();
  const std::vector<float> bias = conv_bias ? conv_bias->to_host() : std::vector<float>();
  std::vector<float> s(g.size()), t(g.size());
  for (size_t c = 0; c < g.size(); ++c) {
    // The same float operations as the cpu batch norm's eval mode: invstd = 1 / sqrt(var + eps).
    const float invstd = 1.0f / std::sqrt(var[c] + eps);
    s[c] = g[c] * invstd;
    t[c] = ((conv_bias ? bias[c] : 0.0f) - m[c]) * s[c] + b[c];
  }
  scale = Tensor::from_host(gamma.backend(), per_channel, s);
  shift = Tensor::from_host(gamma.backend(), per_channel, t);
}

}  // namespace facetool::ops
