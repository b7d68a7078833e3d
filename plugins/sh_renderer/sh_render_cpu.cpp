// CPU entries of the sh_renderer kernel: kernels/sh_render.cl's arithmetic, blocked over pixels.
//
// The forward and backward entries run the per-pixel formulas of kernels/sh_render.cl (whose
// helpers are #included here as C++) on blocks of up to kBlock pixels of one image, with the
// coefficients stored channel by channel, so that the 83-term triple-product sums become short
// loops over contiguous pixels that the compiler vectorises. The light sums reuse the kernel's
// item functions unchanged. tests/renderer checks this against quadrature and against opencl.
#include <algorithm>
#include <cmath>
#include <vector>

#include "plugins/sh_renderer/sh_render_kernel.h"

namespace facetool::sh_render {
namespace cl {
#include "kernels/sh_render.cl"
}  // namespace cl

namespace {

using I = int;
constexpr int kBlock = 64;
constexpr int kCoeffs = SH_COEFFS;

// The [count, 4] table of (i, j, k, T_ijk) rows, unpacked.
struct Table {
  std::vector<int> i, j, k;
  std::vector<float> value;
};

Table unpack_table(const float* rows, int count) {
  Table t;
  for (int r = 0; r < count; ++r) {
    t.i.push_back(static_cast<int>(rows[4 * r]));
    t.j.push_back(static_cast<int>(rows[4 * r + 1]));
    t.k.push_back(static_cast<int>(rows[4 * r + 2]));
    t.value.push_back(rows[4 * r + 3]);
  }
  return t;
}

// Calls fn(n, p0, count) for runs of at most kBlock items of [begin, end) within one image.
template <class Fn>
void for_each_block(int64_t begin, int64_t end, int pixels, Fn fn) {
  for (int64_t item = begin; item < end;) {
    const int n = static_cast<int>(item / pixels);
    const int p0 = static_cast<int>(item - int64_t{n} * pixels);
    const int count = static_cast<int>(std::min<int64_t>({kBlock, end - item, pixels - p0}));
    fn(n, p0, count);
    item += count;
  }
}

// One block's pixels: the unit normal, its length, whether the pixel renders (state > 0, see
// sh_load_normal), the clamped-cosine coefficients c, the visibility v and e = T(v, c).
struct PixelBlock {
  int state[kBlock];
  float unit[3][kBlock], length[kBlock];
  float c[kCoeffs][kBlock], v[kCoeffs][kBlock], e[kCoeffs][kBlock];
};

void load_block(const float* normal, const float* visibility, const float* mask, int has_mask,
                const Table& table, int n, int p0, int count, int pixels, PixelBlock& b) {
  for (int q = 0; q < count; ++q) {
    const int p = p0 + q;
    float unit[3] = {0.0f, 0.0f, 0.0f}, len = 0.0f, c[kCoeffs];
    int state = 0;
    if (!has_mask || mask[n * pixels + p] > 0.5f)
      state = cl::sh_load_normal(normal, n, p, pixels, unit, &len);
    b.state[q] = state;
    b.length[q] = len;
    if (state > 0) {
      cl::sh_cosine_coeffs(unit[0], unit[1], unit[2], c);
    } else {
      std::fill(c, c + kCoeffs, 0.0f);
      std::fill(unit, unit + 3, 0.0f);
    }
    for (int a = 0; a < 3; ++a) b.unit[a][q] = unit[a];
    for (int k = 0; k < kCoeffs; ++k) b.c[k][q] = c[k];
  }
  for (int j = 0; j < kCoeffs; ++j) {
    const float* row = visibility + (n * kCoeffs + j) * pixels + p0;
    for (int q = 0; q < count; ++q) b.v[j][q] = b.state[q] > 0 ? row[q] : 0.0f;
  }
  for (int i = 0; i < kCoeffs; ++i) std::fill(b.e[i], b.e[i] + count, 0.0f);
  const size_t terms = table.value.size();
  for (size_t t = 0; t < terms; ++t) {
    float* e = b.e[table.i[t]];
    const float* v = b.v[table.j[t]];
    const float* c = b.c[table.k[t]];
    const float value = table.value[t];
    for (int q = 0; q < count; ++q) e[q] += value * v[q] * c[q];
  }
}

// s[q] = sum_i l_i e_i[q]: one channel's shading of the block before the 1/pi factor.
void light_dot_e(const float* l, const PixelBlock& b, int count, float* s) {
  std::fill(s, s + count, 0.0f);
  for (int i = 0; i < kCoeffs; ++i)
    for (int q = 0; q < count; ++q) s[q] += l[i] * b.e[i][q];
}

// Arguments as in sh_render_forward of kernels/sh_render.cl.
void forward(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  const float* albedo = a.tensor(0);
  const float* normal = a.tensor(1);
  const float* visibility = a.tensor(2);
  const float* light = a.tensor(3);
  const float* mask = a.tensor(4);
  float* image = a.tensor(6);
  float* shading = a.tensor(7);
  float* invalid = a.tensor(8);
  const int has_mask = a.int_arg(9);
  const int pixels = a.int_arg(11);
  const Table table = unpack_table(a.tensor(5), a.int_arg(10));
  PixelBlock b;
  for_each_block(begin, end, pixels, [&](int n, int p0, int count) {
    load_block(normal, visibility, mask, has_mask, table, n, p0, count, pixels, b);
    for (int q = 0; q < count; ++q)
      invalid[int64_t{n} * pixels + p0 + q] = b.state[q] < 0 ? 1.0f : 0.0f;
    for (int ch = 0; ch < 3; ++ch) {
      float s[kBlock];
      light_dot_e(light + n * 27 + ch * kCoeffs, b, count, s);
      const int64_t at = int64_t{n * 3 + ch} * pixels + p0;
      for (int q = 0; q < count; ++q) {
        const float value = b.state[q] > 0 ? s[q] * SH_INV_PI : 0.0f;
        shading[at + q] = value;
        image[at + q] = b.state[q] > 0 ? albedo[at + q] * value : 0.0f;
      }
    }
  });
}

void store_row(float* out, const float* values, int count, bool accumulate) {
  if (accumulate)
    for (int q = 0; q < count; ++q) out[q] += values[q];
  else
    std::copy(values, values + count, out);
}

// Arguments as in sh_render_backward of kernels/sh_render.cl.
void backward(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  const float* albedo = a.tensor(0);
  const float* normal = a.tensor(1);
  const float* visibility = a.tensor(2);
  const float* light = a.tensor(3);
  const float* mask = a.tensor(4);
  const float* d_image = a.tensor(6);
  const float* d_shading = a.tensor(7);
  float* d_albedo = a.tensor(8);
  float* d_normal = a.tensor(9);
  float* d_visibility = a.tensor(10);
  float* ds_out = a.tensor(11);
  float* e_out = a.tensor(12);
  const int has_mask = a.int_arg(13);
  const int pixels = a.int_arg(15);
  const int flags = a.int_arg(16);
  const Table table = unpack_table(a.tensor(5), a.int_arg(14));
  const size_t terms = table.value.size();
  PixelBlock b;
  for_each_block(begin, end, pixels, [&](int n, int p0, int count) {
    load_block(normal, visibility, mask, has_mask, table, n, p0, count, pixels, b);
    float ds[3][kBlock], da[3][kBlock], de[kCoeffs][kBlock];
    for (int i = 0; i < kCoeffs; ++i) std::fill(de[i], de[i] + count, 0.0f);
    for (int ch = 0; ch < 3; ++ch) {
      const float* l = light + n * 27 + ch * kCoeffs;
      const int64_t at = int64_t{n * 3 + ch} * pixels + p0;
      float s[kBlock];
      light_dot_e(l, b, count, s);
      for (int q = 0; q < count; ++q) {
        const bool on = b.state[q] > 0;
        const float g_image = (flags & SH_HAS_D_IMAGE) ? d_image[at + q] : 0.0f;
        const float g_shading = (flags & SH_HAS_D_SHADING) ? d_shading[at + q] : 0.0f;
        ds[ch][q] = on ? g_image * albedo[at + q] + g_shading : 0.0f;
        da[ch][q] = on ? g_image * (s[q] * SH_INV_PI) : 0.0f;
      }
      for (int i = 0; i < kCoeffs; ++i) {
        const float weight = SH_INV_PI * l[i];
        for (int q = 0; q < count; ++q) de[i][q] += weight * ds[ch][q];
      }
    }
    float dv[kCoeffs][kBlock], dc[kCoeffs][kBlock];
    for (int k = 0; k < kCoeffs; ++k) {
      std::fill(dv[k], dv[k] + count, 0.0f);
      std::fill(dc[k], dc[k] + count, 0.0f);
    }
    if (flags & (SH_WANT_NORMAL | SH_WANT_VISIBILITY)) {
      for (size_t t = 0; t < terms; ++t) {
        const float value = table.value[t];
        const float* dei = de[table.i[t]];
        const float* vj = b.v[table.j[t]];
        const float* ck = b.c[table.k[t]];
        float* dvj = dv[table.j[t]];
        float* dck = dc[table.k[t]];
        for (int q = 0; q < count; ++q) {
          dvj[q] += value * dei[q] * ck[q];
          dck[q] += value * dei[q] * vj[q];
        }
      }
    }
    if (flags & SH_WANT_ALBEDO)
      for (int ch = 0; ch < 3; ++ch)
        store_row(d_albedo + int64_t{n * 3 + ch} * pixels + p0, da[ch], count,
                  flags & SH_ACCUMULATE_ALBEDO);
    if (flags & SH_WANT_NORMAL) {
      float dn[3][kBlock];
      for (int q = 0; q < count; ++q) {
        dn[0][q] = dn[1][q] = dn[2][q] = 0.0f;
        if (b.state[q] <= 0) continue;
        const float unit[3] = {b.unit[0][q], b.unit[1][q], b.unit[2][q]};
        float g[3 * kCoeffs], du[3] = {0.0f, 0.0f, 0.0f};
        cl::sh_cosine_coeffs_gradient(unit[0], unit[1], unit[2], g);
        for (int k = 0; k < kCoeffs; ++k)
          for (int axis = 0; axis < 3; ++axis) du[axis] += dc[k][q] * g[3 * k + axis];
        // Through the normalisation: dn = (du - n^ (n^ . du)) / |n|.
        const float radial = du[0] * unit[0] + du[1] * unit[1] + du[2] * unit[2];
        for (int axis = 0; axis < 3; ++axis)
          dn[axis][q] = (du[axis] - unit[axis] * radial) / b.length[q];
      }
      for (int axis = 0; axis < 3; ++axis)
        store_row(d_normal + int64_t{n * 3 + axis} * pixels + p0, dn[axis], count,
                  flags & SH_ACCUMULATE_NORMAL);
    }
    if (flags & SH_WANT_VISIBILITY)
      for (int j = 0; j < kCoeffs; ++j)
        store_row(d_visibility + int64_t{n * kCoeffs + j} * pixels + p0, dv[j], count,
                  flags & SH_ACCUMULATE_VISIBILITY);
    if (flags & SH_WANT_LIGHT) {
      for (int ch = 0; ch < 3; ++ch)
        std::copy(ds[ch], ds[ch] + count, ds_out + int64_t{n * 3 + ch} * pixels + p0);
      for (int i = 0; i < kCoeffs; ++i)
        std::copy(b.e[i], b.e[i] + count, e_out + int64_t{n * kCoeffs + i} * pixels + p0);
    }
  });
}

void light_partial(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    cl::sh_light_partial_item(static_cast<I>(item), a.tensor(0), a.tensor(1), a.tensor(2),
                              a.int_arg(3), a.int_arg(4), a.int_arg(5));
}

void reduce_rows(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    cl::sh_reduce_rows_item(static_cast<I>(item), a.tensor(0), a.tensor(1), a.int_arg(2),
                            a.int_arg(3), a.int_arg(4), a.int_arg(5));
}

}  // namespace

std::map<std::string, CpuKernelFn> cpu_entries() {
  return {{kForwardEntry, &forward},
          {kBackwardEntry, &backward},
          {kLightPartialEntry, &light_partial},
          {kReduceRowsEntry, &reduce_rows}};
}

}  // namespace facetool::sh_render
