// OpenclBackend element-wise ops, activations, channel copies and the Adam update.
#include <cmath>

#include "backends/opencl/opencl_backend.h"

namespace facetool::opencl {

static const char* kElementwise = "elementwise.cl";
static const char* kActivations = "activations.cl";

void OpenclBackend::fill(const Tensor& t, float value) {
  run_kernel(*this, kElementwise, "fill", t.numel(), t, value, t.numel());
}

void OpenclBackend::copy(const Tensor& src, const Tensor& dst) {
  run_kernel(*this, kElementwise, "copy", dst.numel(), src, dst, dst.numel());
}

void OpenclBackend::copy_channels(const Tensor& x, int64_t src_c0, const Tensor& y,
                                  int64_t dst_c0, int64_t count, bool accumulate) {
  const Shape& xs = x.shape();
  const int64_t plane = xs.h() * xs.w();
  run_nd(*this, kElementwise, "copy_channels", {plane, xs.n() * count}, x, xs.c(), src_c0, y,
         y.shape().c(), dst_c0, count, plane, accumulate);
}

void OpenclBackend::add(const Tensor& a, const Tensor& b, const Tensor& y) {
  run_kernel(*this, kElementwise, "add", y.numel(), a, b, y, y.numel());
}

void OpenclBackend::mul(const Tensor& a, const Tensor& b, const Tensor& y) {
  run_kernel(*this, kElementwise, "mul", y.numel(), a, b, y, y.numel());
}

void OpenclBackend::scale(const Tensor& x, float alpha, const Tensor& y) {
  run_kernel(*this, kElementwise, "scale", y.numel(), x, alpha, y, y.numel());
}

void OpenclBackend::axpy(float alpha, const Tensor& x, const Tensor& y) {
  run_kernel(*this, kElementwise, "axpy", y.numel(), alpha, x, y, y.numel());
}

void OpenclBackend::mul_backward(const Tensor& a, const Tensor& b, const Tensor& dy,
                                 const Tensor* da, const Tensor* db, bool accumulate) {
  const int64_t n = dy.numel();
  if (da) run_kernel(*this, kElementwise, "mul_grad", n, b, dy, *da, accumulate, n);
  if (db) run_kernel(*this, kElementwise, "mul_grad", n, a, dy, *db, accumulate, n);
}

void OpenclBackend::leaky_relu(const Tensor& x, float slope, const Tensor& y) {
  run_kernel(*this, kActivations, "leaky_relu", y.numel(), x, slope, y, y.numel());
}

void OpenclBackend::leaky_relu_backward(const Tensor& x, float slope, const Tensor& dy,
                                        const Tensor& dx, bool accumulate) {
  run_kernel(*this, kActivations, "leaky_relu_backward", dx.numel(), x, slope, dy, dx, accumulate,
             dx.numel());
}

void OpenclBackend::sigmoid(const Tensor& x, const Tensor& y) {
  run_kernel(*this, kActivations, "sigmoid", y.numel(), x, y, y.numel());
}

void OpenclBackend::sigmoid_backward(const Tensor& y, const Tensor& dy, const Tensor& dx,
                                     bool accumulate) {
  run_kernel(*this, kActivations, "sigmoid_backward", dx.numel(), y, dy, dx, accumulate,
             dx.numel());
}

void OpenclBackend::adam_step(const Tensor& param, const Tensor& grad, const Tensor& m,
                              const Tensor& v, const AdamParams& p) {
  const double t = static_cast<double>(p.step);
  const double bias_correction1 = 1.0 - std::pow(static_cast<double>(p.beta1), t);
  const double bias_correction2 = 1.0 - std::pow(static_cast<double>(p.beta2), t);
  const float step_size = static_cast<float>(p.lr / bias_correction1);
  const float bc2_sqrt = static_cast<float>(std::sqrt(bias_correction2));
  run_kernel(*this, "adam.cl", "adam_step", param.numel(), param, grad, m, v, p.beta1, p.beta2,
             p.eps, p.weight_decay, step_size, bc2_sqrt, param.numel());
}

}  // namespace facetool::opencl
