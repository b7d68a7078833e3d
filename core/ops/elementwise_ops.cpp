// Op functions: fill, copy, add, mul, scale, axpy, leaky ReLU and sigmoid.
#include "core/ops/checks.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ops {

using namespace detail;

void fill(const Tensor& t, float value) {
  require_data("fill", "tensor", t);
  t.backend().fill(t, value);
}

void copy(const Tensor& src, const Tensor& dst) {
  require_data("copy", "source", src);
  require_data("copy", "destination", dst);
  check(src.numel() == dst.numel(), "copy: size mismatch: source ", src.shape().str(),
        " vs destination ", dst.shape().str());
  if (&src.backend() == &dst.backend()) {
    src.backend().copy(src, dst);
  } else {
    std::vector<float> host = src.to_host();
    dst.backend().upload(dst, host.data());
  }
}

Tensor add(const Tensor& a, const Tensor& b) {
  require_same_shape("add", "a", a, "b", b);
  require_same_backend("add", a, {&b});
  Tensor y = Tensor::empty(a.backend(), a.shape());
  a.backend().add(a, b, y);
  return y;
}

static void pass_gradient(const char* op, const Tensor& dy, float alpha, const Tensor* dx,
                          bool accumulate) {
  if (dx == nullptr) return;
  require_same_shape(op, "dy", dy, "dx", *dx);
  require_same_backend(op, dy, {dx});
  if (accumulate)
    dy.backend().axpy(alpha, dy, *dx);
  else
    dy.backend().scale(dy, alpha, *dx);
}

void add_backward(const Tensor& dy, const Tensor* da, const Tensor* db, bool accumulate) {
  pass_gradient("add_backward", dy, 1.0f, da, accumulate);
  pass_gradient("add_backward", dy, 1.0f, db, accumulate);
}

Tensor mul(const Tensor& a, const Tensor& b) {
  require_same_shape("mul", "a", a, "b", b);
  require_same_backend("mul", a, {&b});
  Tensor y = Tensor::empty(a.backend(), a.shape());
  a.backend().mul(a, b, y);
  return y;
}

void mul_backward(const Tensor& a, const Tensor& b, const Tensor& dy, const Tensor* da,
                  const Tensor* db, bool accumulate) {
  require_same_shape("mul_backward", "a", a, "b", b);
  require_same_shape("mul_backward", "a", a, "dy", dy);
  if (da) require_same_shape("mul_backward", "a", a, "da", *da);
  if (db) require_same_shape("mul_backward", "b", b, "db", *db);
  require_same_backend("mul_backward", a, {&b, &dy, da, db});
  if (da || db) a.backend().mul_backward(a, b, dy, da, db, accumulate);
}

Tensor scale(const Tensor& x, float alpha) {
  require_data("scale", "x", x);
  Tensor y = Tensor::empty(x.backend(), x.shape());
  x.backend().scale(x, alpha, y);
  return y;
}

void scale_backward(const Tensor& dy, float alpha, const Tensor& dx, bool accumulate) {
  pass_gradient("scale_backward", dy, alpha, &dx, accumulate);
}

void axpy(float alpha, const Tensor& x, const Tensor& y) {
  require_same_shape("axpy", "x", x, "y", y);
  require_same_backend("axpy", x, {&y});
  x.backend().axpy(alpha, x, y);
}

Tensor leaky_relu(const Tensor& x, float slope) {
  require_data("leaky_relu", "x", x);
  Tensor y = Tensor::empty(x.backend(), x.shape());
  x.backend().leaky_relu(x, slope, y);
  return y;
}

void leaky_relu_backward(const Tensor& x, float slope, const Tensor& dy, const Tensor& dx,
                         bool accumulate) {
  require_same_shape("leaky_relu_backward", "x", x, "dy", dy);
  require_same_shape("leaky_relu_backward", "x", x, "dx", dx);
  require_same_backend("leaky_relu_backward", x, {&dy, &dx});
  x.backend().leaky_relu_backward(x, slope, dy, dx, accumulate);
}

Tensor sigmoid(const Tensor& x) {
  require_data("sigmoid", "x", x);
  Tensor y = Tensor::empty(x.backend(), x.shape());
  x.backend().sigmoid(x, y);
  return y;
}

void sigmoid_backward(const Tensor& y, const Tensor& dy, const Tensor& dx, bool accumulate) {
  require_same_shape("sigmoid_backward", "y", y, "dy", dy);
  require_same_shape("sigmoid_backward", "y", y, "dx", dx);
  require_same_backend("sigmoid_backward", y, {&dy, &dx});
  y.backend().sigmoid_backward(y, dy, dx, accumulate);
}

}  // namespace facetool::ops
