// im2col and col2im over blocks of output pixels, one kernel tap (row of col) at a time.
#include "backends/cpu/cpu_im2col.h"

#include <algorithm>

namespace facetool::cpu {
namespace {

// Output columns [lo, hi) of a row of length out_width whose input column ox*stride - pad + kx
// lies inside [0, width).
void valid_columns(const ConvGeometry& g, int64_t kx, int64_t ox0, int64_t ox1, int64_t* lo,
                   int64_t* hi) {
  const int64_t offset = kx - g.pad;  // ix = ox * stride + offset
  int64_t first = offset >= 0 ? 0 : (-offset + g.stride - 1) / g.stride;
  int64_t last = (g.width - 1 - offset) >= 0 ? (g.width - 1 - offset) / g.stride + 1 : 0;
  *lo = std::clamp(first, ox0, ox1);
  *hi = std::clamp(last, *lo, ox1);
}

// Calls visit(dst_offset, oy, ox0, ox1) for each output-row segment of pixels [p0, p0 + count).
template <typename Visit>
void for_each_row_segment(const ConvGeometry& g, int64_t p0, int64_t count, Visit visit) {
  int64_t p = p0;
  const int64_t end = p0 + count;
  while (p < end) {
    const int64_t oy = p / g.out_width;
    const int64_t ox0 = p % g.out_width;
    const int64_t ox1 = std::min(g.out_width, ox0 + (end - p));
    visit(p - p0, oy, ox0, ox1);
    p += ox1 - ox0;
  }
}

}  // namespace

void im2col_block(const ConvGeometry& g, const float* image, int64_t c0, int64_t c1, int64_t p0,
                  int64_t count, float* col) {
  const int64_t k = g.kernel;
  const int64_t s = g.stride;
  for (int64_t c = c0; c < c1; ++c) {
    for (int64_t ky = 0; ky < k; ++ky) {
      for (int64_t kx = 0; kx < k; ++kx) {
        float* dst = col + (((c - c0) * k + ky) * k + kx) * count;
        for_each_row_segment(g, p0, count, [&](int64_t at, int64_t oy, int64_t ox0, int64_t ox1) {
          float* seg = dst + at;  // seg[ox - ox0] holds output column ox
          const int64_t iy = oy * s - g.pad + ky;
          if (iy < 0 || iy >= g.height) {
            std::fill(seg, seg + (ox1 - ox0), 0.0f);
            return;
          }
          int64_t lo, hi;
          valid_columns(g, kx, ox0, ox1, &lo, &hi);
          std::fill(seg, seg + (lo - ox0), 0.0f);
          const float* row = image + (c * g.height + iy) * g.width;
          const int64_t offset = kx - g.pad;  // input column of output column ox: ox*s + offset
          if (s == 1) {
            std::copy(row + lo + offset, row + hi + offset, seg + (lo - ox0));
          } else {
            for (int64_t ox = lo; ox < hi; ++ox) seg[ox - ox0] = row[ox * s + offset];
          }
          std::fill(seg + (hi - ox0), seg + (ox1 - ox0), 0.0f);
        });
      }
    }
  }
}

void col2im_block_add(const ConvGeometry& g, const float* col, int64_t c0, int64_t c1, int64_t p0,
                      int64_t count, float* image) {
  const int64_t k = g.kernel;
  const int64_t s = g.stride;
  for (int64_t c = c0; c < c1; ++c) {
    for (int64_t ky = 0; ky < k; ++ky) {
      for (int64_t kx = 0; kx < k; ++kx) {
        const float* src = col + (((c - c0) * k + ky) * k + kx) * count;
        for_each_row_segment(g, p0, count, [&](int64_t at, int64_t oy, int64_t ox0, int64_t ox1) {
          const int64_t iy = oy * s - g.pad + ky;
          if (iy < 0 || iy >= g.height) return;
          const float* seg = src + at;
          int64_t lo, hi;
          valid_columns(g, kx, ox0, ox1, &lo, &hi);
          float* row = image + (c * g.height + iy) * g.width;
          const int64_t offset = kx - g.pad;
          for (int64_t ox = lo; ox < hi; ++ox) row[ox * s + offset] += seg[ox - ox0];
        });
      }
    }
  }
}

}  // namespace facetool::cpu
