// Bilinear 2x upsampling (align_corners=False) and global average pooling on the cpu.
#include <algorithm>

#include "backends/cpu/cpu_backend_impl.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {
namespace {

// Source taps of output index `o` along an axis of `size` input samples, PyTorch's rule for
// scale 2 without corner alignment: src = (o + 0.5) / 2 - 0.5 clamped at 0.
struct Taps {
  int64_t i0, i1;
  float w0, w1;
};

Taps taps(int64_t o, int64_t size) {
  const float src = std::max(0.0f, (static_cast<float>(o) + 0.5f) * 0.5f - 0.5f);
  Taps t;
  t.i0 = std::min(static_cast<int64_t>(src), size - 1);
  t.i1 = std::min(t.i0 + 1, size - 1);
  t.w1 = src - static_cast<float>(t.i0);
  t.w0 = 1.0f - t.w1;
  return t;
}

// Runs fn(plane index) for every (n, c) plane, in parallel.
template <typename Fn>
void for_each_plane(int64_t planes, int64_t plane_size, Fn fn) {
  parallel_for(planes, std::max<int64_t>(1, kElementwiseGrain / plane_size),
               [&](int64_t begin, int64_t end) {
                 for (int64_t q = begin; q < end; ++q) fn(q);
               });
}

}  // namespace

void CpuBackend::upsample_bilinear2x(const Tensor& x, const Tensor& y) {
  const Shape& s = x.shape();
  const int64_t h = s.h(), w = s.w(), oh = 2 * h, ow = 2 * w;
  const float* px = ptr(x);
  float* py = ptr(y);
  for_each_plane(s.n() * s.c(), oh * ow, [&](int64_t q) {
    const float* in = px + q * h * w;
    float* out = py + q * oh * ow;
    for (int64_t oy = 0; oy < oh; ++oy) {
      const Taps ty = taps(oy, h);
      for (int64_t ox = 0; ox < ow; ++ox) {
        const Taps tx = taps(ox, w);
        out[oy * ow + ox] = ty.w0 * (tx.w0 * in[ty.i0 * w + tx.i0] + tx.w1 * in[ty.i0 * w + tx.i1]) +
                            ty.w1 * (tx.w0 * in[ty.i1 * w + tx.i0] + tx.w1 * in[ty.i1 * w + tx.i1]);
      }
    }
  });
}

void CpuBackend::upsample_bilinear2x_backward(const Tensor& dy, const Tensor& dx,
                                              bool accumulate) {
  const Shape& s = dx.shape();
  const int64_t h = s.h(), w = s.w(), oh = 2 * h, ow = 2 * w;
  const float* pdy = ptr(dy);
  float* pdx = ptr(dx);
  for_each_plane(s.n() * s.c(), oh * ow, [&](int64_t q) {
    const float* g = pdy + q * oh * ow;
    float* out = pdx + q * h * w;
    if (!accumulate) std::fill(out, out + h * w, 0.0f);
    for (int64_t oy = 0; oy < oh; ++oy) {
      const Taps ty = taps(oy, h);
      for (int64_t ox = 0; ox < ow; ++ox) {
        const Taps tx = taps(ox, w);
        const float v = g[oy * ow + ox];
        out[ty.i0 * w + tx.i0] += ty.w0 * tx.w0 * v;
        out[ty.i0 * w + tx.i1] += ty.w0 * tx.w1 * v;
        out[ty.i1 * w + tx.i0] += ty.w1 * tx.w0 * v;
        out[ty.i1 * w + tx.i1] += ty.w1 * tx.w1 * v;
      }
    }
  });
}

void CpuBackend::global_avg_pool(const Tensor& x, const Tensor& y) {
  const Shape& s = x.shape();
  const int64_t plane = s.h() * s.w();
  const float* px = ptr(x);
  float* py = ptr(y);
  for_each_plane(s.n() * s.c(), plane, [&](int64_t q) {
    double total = 0.0;
    for (int64_t i = 0; i < plane; ++i) total += px[q * plane + i];
    py[q] = static_cast<float>(total / static_cast<double>(plane));
  });
}

void CpuBackend::global_avg_pool_backward(const Tensor& dy, const Tensor& dx, bool accumulate) {
  const Shape& s = dx.shape();
  const int64_t plane = s.h() * s.w();
  const float* pdy = ptr(dy);
  float* pdx = ptr(dx);
  for_each_plane(s.n() * s.c(), plane, [&](int64_t q) {
    const float g = pdy[q] / static_cast<float>(plane);
    for (int64_t i = 0; i < plane; ++i) store(pdx[q * plane + i], g, accumulate);
  });
}

}  // namespace facetool::cpu
