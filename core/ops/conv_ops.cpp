// Op functions: 2-D convolution and the fully connected layer.
#include "core/ops/checks.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ops {

using namespace detail;

static Shape conv_output_shape(const Tensor& x, const Tensor& w, const Tensor* bias,
                               const Conv2dParams& p) {
  require_nchw("conv2d", "input x", x);
  require_nchw("conv2d", "weight w", w);
  const Shape& xs = x.shape();
  const Shape& ws = w.shape();
  check(ws.h() == ws.w() && ws.h() % 2 == 1, "conv2d: the kernel must be square with an odd size, ",
        "got weight ", ws.str());
  check(ws.c() == xs.c(), "conv2d: weight ", ws.str(), " expects ", ws.c(),
        " input channels but x ", xs.str(), " has ", xs.c());
  check(p.stride >= 1, "conv2d: stride must be >= 1, got ", p.stride);
  const int pad = p.effective_pad(ws.h());
  const int64_t ho = (xs.h() + 2 * pad - ws.h()) / p.stride + 1;
  const int64_t wo = (xs.w() + 2 * pad - ws.w()) / p.stride + 1;
  check(xs.h() + 2 * pad >= ws.h() && xs.w() + 2 * pad >= ws.w(), "conv2d: input x ", xs.str(),
        " with padding ", pad, " is smaller than the kernel of weight ", ws.str());
  if (bias) require_shape("conv2d", "bias", *bias, Shape{ws.n()});
  require_same_backend("conv2d", x, {&w, bias});
  return Shape{xs.n(), ws.n(), ho, wo};
}

Tensor conv2d(const Tensor& x, const Tensor& w, const Tensor* bias, const Conv2dParams& p) {
  Shape ys = conv_output_shape(x, w, bias, p);
  Tensor y = Tensor::empty(x.backend(), ys);
  x.backend().conv2d(x, w, bias, y, p);
  return y;
}

void conv2d_backward(const Tensor& x, const Tensor& w, const Tensor& dy, const Tensor* dx,
                     const Tensor* dw, const Tensor* dbias, const Conv2dParams& p,
                     bool accumulate) {
  Shape ys = conv_output_shape(x, w, nullptr, p);
  require_shape("conv2d_backward", "dy", dy, ys);
  if (dx) require_same_shape("conv2d_backward", "x", x, "dx", *dx);
  if (dw) require_same_shape("conv2d_backward", "w", w, "dw", *dw);
  if (dbias) require_shape("conv2d_backward", "dbias", *dbias, Shape{w.shape().n()});
  require_same_backend("conv2d_backward", x, {&dy, dx, dw, dbias});
  if (dx || dw || dbias) x.backend().conv2d_backward(x, w, dy, dx, dw, dbias, p, accumulate);
}

static Shape linear_output_shape(const char* op, const Tensor& x, const Tensor& w,
                                 const Tensor* bias) {
  require_data(op, "input x", x);
  require_data(op, "weight w", w);
  check(x.shape().rank() == 2 && w.shape().rank() == 2, op, ": x [N, in] and w [out, in] ",
        "must have rank 2, got x ", x.shape().str(), " and w ", w.shape().str());
  check(x.shape()[1] == w.shape()[1], op, ": x ", x.shape().str(), " has ", x.shape()[1],
        " features but w ", w.shape().str(), " expects ", w.shape()[1]);
  if (bias) require_shape(op, "bias", *bias, Shape{w.shape()[0]});
  require_same_backend(op, x, {&w, bias});
  return Shape{x.shape()[0], w.shape()[0]};
}

Tensor linear(const Tensor& x, const Tensor& w, const Tensor* bias) {
  Tensor y = Tensor::empty(x.backend(), linear_output_shape("linear", x, w, bias));
  x.backend().linear(x, w, bias, y);
  return y;
}

void linear_backward(const Tensor& x, const Tensor& w, const Tensor& dy, const Tensor* dx,
                     const Tensor* dw, const Tensor* dbias, bool accumulate) {
  require_shape("linear_backward", "dy", dy, linear_output_shape("linear_backward", x, w, nullptr));
  if (dx) require_same_shape("linear_backward", "x", x, "dx", *dx);
  if (dw) require_same_shape("linear_backward", "w", w, "dw", *dw);
  if (dbias) require_shape("linear_backward", "dbias", *dbias, Shape{w.shape()[0]});
  require_same_backend("linear_backward", x, {&dy, dx, dw, dbias});
  if (dx || dw || dbias) x.backend().linear_backward(x, w, dy, dx, dw, dbias, accumulate);
}

}  // namespace facetool::ops
