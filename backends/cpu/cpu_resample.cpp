// Bilinear 2x upsampling (align_corners=False) and global average pooling on the cpu.
#include <algorithm>

#include "backends/cpu/cpu_backend_impl.h"
#include "backends/cpu/cpu_workspace.h"
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

// One row upsampled 2x along x: out[2k] = 0.25 in[k-1] + 0.75 in[k] and out[2k+1] = 0.75 in[k] +
// 0.25 in[k+1], the neighbours clamped at the row's ends (what taps() gives, without its
// per-pixel arithmetic).
void upsample_row(const float* in, int64_t w, float* out) {
  for (int64_t k = 0; k < w; ++k) {
    const float left = in[k > 0 ? k - 1 : 0], right = in[k + 1 < w ? k + 1 : w - 1];
    out[2 * k] = 0.25f * left + 0.75f * in[k];
    out[2 * k + 1] = 0.75f * in[k] + 0.25f * right;
  }
}

// in[k] (+)= the gradient upsample_row sends back from g (2w values).
void upsample_row_adjoint(const float* g, int64_t w, float* in, bool accumulate) {
  for (int64_t k = 0; k < w; ++k) {
    float total = 0.75f * (g[2 * k] + g[2 * k + 1]);
    total += 0.25f * (k + 1 < w ? g[2 * k + 2] : g[2 * k + 1]);  // right neighbour's left tap
    total += 0.25f * (k > 0 ? g[2 * k - 1] : g[2 * k]);          // left neighbour's right tap
    store(in[k], total, accumulate);
  }
}

// out = w0 a + w1 b over n values.
void blend_rows(const float* __restrict a, float w0, const float* __restrict b, float w1,
                int64_t n, float* __restrict out) {
  for (int64_t i = 0; i < n; ++i) out[i] = w0 * a[i] + w1 * b[i];
}

// out += scale * g over n values.
void add_scaled_row(const float* __restrict g, float scale, int64_t n, float* __restrict out) {
  for (int64_t i = 0; i < n; ++i) out[i] += scale * g[i];
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
    // Separable: every input row upsampled along x once, then output rows blend two of them.
    float* wide = thread_workspace(static_cast<size_t>(h * ow));
    for (int64_t iy = 0; iy < h; ++iy) upsample_row(in + iy * w, w, wide + iy * ow);
    for (int64_t oy = 0; oy < oh; ++oy) {
      const Taps ty = taps(oy, h);
      blend_rows(wide + ty.i0 * ow, ty.w0, wide + ty.i1 * ow, ty.w1, ow, out + oy * ow);
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
    // The adjoint of the forward's two steps: rows summed into their taps, then along x.
    float* wide = thread_workspace(static_cast<size_t>(h * ow));
    std::fill(wide, wide + h * ow, 0.0f);
    for (int64_t oy = 0; oy < oh; ++oy) {
      const Taps ty = taps(oy, h);
      add_scaled_row(g + oy * ow, ty.w0, ow, wide + ty.i0 * ow);
      add_scaled_row(g + oy * ow, ty.w1, ow, wide + ty.i1 * ow);
    }
    for (int64_t iy = 0; iy < h; ++iy)
      upsample_row_adjoint(wide + iy * ow, w, out + iy * w, accumulate);
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
