// Op functions: bilinear 2x upsampling and global average pooling.
#include "core/ops/checks.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ops {

using namespace detail;

Tensor upsample_bilinear2x(const Tensor& x) {
  require_nchw("upsample_bilinear2x", "x", x);
  const Shape& s = x.shape();
  Tensor y = Tensor::empty(x.backend(), Shape{s.n(), s.c(), 2 * s.h(), 2 * s.w()});
  x.backend().upsample_bilinear2x(x, y);
  return y;
}

void upsample_bilinear2x_backward(const Tensor& dy, const Tensor& dx, bool accumulate) {
  require_nchw("upsample_bilinear2x_backward", "dx", dx);
  const Shape& s = dx.shape();
  require_shape("upsample_bilinear2x_backward", "dy", dy,
                Shape{s.n(), s.c(), 2 * s.h(), 2 * s.w()});
  require_same_backend("upsample_bilinear2x_backward", dy, {&dx});
  dy.backend().upsample_bilinear2x_backward(dy, dx, accumulate);
}

Tensor global_avg_pool(const Tensor& x) {
  require_nchw("global_avg_pool", "x", x);
  Tensor y = Tensor::empty(x.backend(), Shape{x.shape().n(), x.shape().c()});
  x.backend().global_avg_pool(x, y);
  return y;
}

void global_avg_pool_backward(const Tensor& dy, const Tensor& dx, bool accumulate) {
  require_nchw("global_avg_pool_backward", "dx", dx);
  require_shape("global_avg_pool_backward", "dy", dy, Shape{dx.shape().n(), dx.shape().c()});
  require_same_backend("global_avg_pool_backward", dy, {&dx});
  dy.backend().global_avg_pool_backward(dy, dx, accumulate);
}

}  // namespace facetool::ops
