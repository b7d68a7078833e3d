// Per-pixel L2 normalisation over channels (F.normalize semantics) on the cpu.
#include <algorithm>
#include <cmath>

#include "backends/cpu/cpu_backend_impl.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {
namespace {

// Runs fn(image base offset, pixel) for every pixel of an NCHW tensor, in parallel.
template <typename Fn>
void for_each_pixel(const Shape& s, Fn fn) {
  const int64_t plane = s.h() * s.w();
  parallel_for(s.n() * plane, 4096, [&](int64_t begin, int64_t end) {
    for (int64_t t = begin; t < end; ++t) fn((t / plane) * s.c() * plane, t % plane);
  });
}

}  // namespace

void CpuBackend::l2_normalize(const Tensor& x, float eps, const Tensor& y) {
  const Shape& s = x.shape();
  const int64_t plane = s.h() * s.w();
  const float* px = ptr(x);
  float* py = ptr(y);
  for_each_pixel(s, [&](int64_t base, int64_t i) {
    float squares = 0.0f;
    for (int64_t c = 0; c < s.c(); ++c) squares += px[base + c * plane + i] * px[base + c * plane + i];
    const float norm = std::sqrt(squares);
    const float denom = norm >= eps ? norm : eps;  // NaN norm stays NaN
    for (int64_t c = 0; c < s.c(); ++c) py[base + c * plane + i] = px[base + c * plane + i] / denom;
  });
}

void CpuBackend::l2_normalize_backward(const Tensor& x, float eps, const Tensor& dy,
                                       const Tensor& dx, bool accumulate) {
  const Shape& s = x.shape();
  const int64_t plane = s.h() * s.w();
  const float* px = ptr(x);
  const float* pdy = ptr(dy);
  float* pdx = ptr(dx);
  for_each_pixel(s, [&](int64_t base, int64_t i) {
    float squares = 0.0f, dot = 0.0f;
    for (int64_t c = 0; c < s.c(); ++c) {
      const float v = px[base + c * plane + i];
      squares += v * v;
      dot += v * pdy[base + c * plane + i];
    }
    const float norm = std::sqrt(squares);
    if (norm < eps) {
      // The denominator is the constant eps: dx = dy / eps.
      for (int64_t c = 0; c < s.c(); ++c)
        store(pdx[base + c * plane + i], pdy[base + c * plane + i] / eps, accumulate);
      return;
    }
    // d(x/|x|) = dy/|x| - x (x . dy) / |x|^3
    const float inv = 1.0f / norm;
    const float k = dot * inv * inv * inv;
    for (int64_t c = 0; c < s.c(); ++c) {
      const int64_t at = base + c * plane + i;
      store(pdx[at], pdy[at] * inv - px[at] * k, accumulate);
    }
  });
}

}  // namespace facetool::cpu
