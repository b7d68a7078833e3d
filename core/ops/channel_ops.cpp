// Op functions: channel concatenation and slicing.
#include "core/ops/checks.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ops {

using namespace detail;

static void require_same_nhw(const char* op, const Tensor& a, const Tensor& b) {
  check(a.shape().n() == b.shape().n() && a.shape().h() == b.shape().h() &&
            a.shape().w() == b.shape().w(),
        op, ": N, H and W must agree: ", a.shape().str(), " vs ", b.shape().str());
}

Tensor concat_channels(const std::vector<Tensor>& xs) {
  check(!xs.empty(), "concat_channels: no inputs");
  int64_t channels = 0;
  for (const Tensor& x : xs) {
    require_nchw("concat_channels", "input", x);
    require_same_nhw("concat_channels", xs[0], x);
    require_same_backend("concat_channels", xs[0], {&x});
    channels += x.shape().c();
  }
  const Shape& s = xs[0].shape();
  Tensor y = Tensor::empty(xs[0].backend(), Shape{s.n(), channels, s.h(), s.w()});
  int64_t c0 = 0;
  for (const Tensor& x : xs) {
    y.backend().copy_channels(x, 0, y, c0, x.shape().c(), false);
    c0 += x.shape().c();
  }
  return y;
}

void concat_channels_backward(const Tensor& dy, const std::vector<const Tensor*>& dxs,
                              bool accumulate) {
  require_nchw("concat_channels_backward", "dy", dy);
  int64_t c0 = 0;
  for (const Tensor* dx : dxs) {
    check(dx != nullptr, "concat_channels_backward: every input needs a gradient tensor");
    require_nchw("concat_channels_backward", "dx", *dx);
    require_same_nhw("concat_channels_backward", dy, *dx);
    require_same_backend("concat_channels_backward", dy, {dx});
    check(c0 + dx->shape().c() <= dy.shape().c(), "concat_channels_backward: gradients ",
          "hold more channels than dy ", dy.shape().str());
    dy.backend().copy_channels(dy, c0, *dx, 0, dx->shape().c(), accumulate);
    c0 += dx->shape().c();
  }
  check(c0 == dy.shape().c(), "concat_channels_backward: gradients hold ", c0,
        " channels but dy ", dy.shape().str(), " has ", dy.shape().c());
}

Tensor slice_channels(const Tensor& x, int64_t c0, int64_t count) {
  require_nchw("slice_channels", "x", x);
  check(c0 >= 0 && count > 0 && c0 + count <= x.shape().c(), "slice_channels: channels [", c0,
        ", ", c0 + count, ") are outside x ", x.shape().str());
  const Shape& s = x.shape();
  Tensor y = Tensor::empty(x.backend(), Shape{s.n(), count, s.h(), s.w()});
  x.backend().copy_channels(x, c0, y, 0, count, false);
  return y;
}

void slice_channels_backward(const Tensor& dy, int64_t c0, const Tensor& dx, bool accumulate) {
  require_nchw("slice_channels_backward", "dy", dy);
  require_nchw("slice_channels_backward", "dx", dx);
  require_same_nhw("slice_channels_backward", dy, dx);
  require_same_backend("slice_channels_backward", dy, {&dx});
  const int64_t count = dy.shape().c();
  check(c0 >= 0 && c0 + count <= dx.shape().c(), "slice_channels_backward: channels [", c0, ", ",
        c0 + count, ") are outside dx ", dx.shape().str());
  if (!accumulate) dx.backend().fill(dx, 0.0f);
  dx.backend().copy_channels(dy, 0, dx, c0, count, accumulate);
}

}  // namespace facetool::ops
