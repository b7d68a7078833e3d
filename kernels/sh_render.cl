// sh_render.cl: per-pixel SH triple-product rendering, its backward pass and light-gradient sums.
//
// Written once for both targets: built as OpenCL C 1.2 (the __kernel wrappers at the end) and
// #included as C++ by plugins/sh_renderer/sh_render_cpu.cpp, whose CPU entries share the helper
// functions and run the same per-pixel formulas on blocks of pixels (vectorised over pixels).
//
// Layouts (P = H * W pixels per image, item = n * P + p):
//   albedo, normal, image, shading [N,3,P]; visibility [N,9,P]; light [N,27] channel-major;
//   mask [N,1,P] (a pixel is rendered when mask > 0.5); table [count,4] = (i, j, k, T_ijk),
//   the nonzero tripling coefficients of core/sh/triple_product.h in every index order.
// Per pixel: n^ = normal / |normal|; c_k = A_l Y_k(n^) (clamped cosine, A = pi, 2pi/3, pi/4);
//   e_i = sum_jk T_ijk v_j c_k; shading_ch = (1/pi) sum_i L_ch,i e_i; image = albedo * shading.
// Pixels outside the mask, and normals shorter than SH_MIN_NORMAL_LENGTH, give 0 and a zero
// gradient. Non-finite normals of rendered pixels set invalid[item] = 1 (the host then fails).

#ifdef __OPENCL_VERSION__
#define SH_GLOBAL __global
#define SH_SQRT(x) sqrt(x)
#define SH_ISFINITE(x) isfinite(x)
#else
#define SH_GLOBAL
#define SH_SQRT(x) std::sqrt(x)
#define SH_ISFINITE(x) std::isfinite(x)
#endif

#define SH_COEFFS 9
#define SH_INV_PI 0.318309886183790672f
#define SH_MIN_NORMAL_LENGTH 1e-8f

// Y_0..Y_8 (core/sh/sh_basis.h) times the clamped-cosine band factors A_l, at unit (x, y, z).
void sh_cosine_coeffs(float x, float y, float z, float* c) {
  const float a0 = 3.14159265358979323846f, a1 = 2.09439510239319549f, a2 = 0.785398163397448310f;
  c[0] = a0 * 0.282094791773878143f;
  c[1] = a1 * 0.488602511902919922f * y;
  c[2] = a1 * 0.488602511902919922f * z;
  c[3] = a1 * 0.488602511902919922f * x;
  c[4] = a2 * 1.09254843059207907f * x * y;
  c[5] = a2 * 1.09254843059207907f * y * z;
  c[6] = a2 * 0.315391565252520006f * (3.0f * z * z - 1.0f);
  c[7] = a2 * 1.09254843059207907f * x * z;
  c[8] = a2 * 0.546274215296039535f * (x * x - y * y);
}

// Gradient of sh_cosine_coeffs with respect to (x, y, z): g[3 k + axis].
void sh_cosine_coeffs_gradient(float x, float y, float z, float* g) {
  const float a1 = 2.09439510239319549f * 0.488602511902919922f;
  const float a2 = 0.785398163397448310f * 1.09254843059207907f;
  const float a20 = 0.785398163397448310f * 0.315391565252520006f;
  const float a22 = 0.785398163397448310f * 0.546274215296039535f;
  for (int k = 0; k < 3 * SH_COEFFS; ++k) g[k] = 0.0f;
  g[3 * 1 + 1] = a1;
  g[3 * 2 + 2] = a1;
  g[3 * 3 + 0] = a1;
  g[3 * 4 + 0] = a2 * y;        g[3 * 4 + 1] = a2 * x;
  g[3 * 5 + 1] = a2 * z;        g[3 * 5 + 2] = a2 * y;
  g[3 * 6 + 2] = 6.0f * a20 * z;
  g[3 * 7 + 0] = a2 * z;        g[3 * 7 + 2] = a2 * x;
  g[3 * 8 + 0] = 2.0f * a22 * x; g[3 * 8 + 1] = -2.0f * a22 * y;
}

// Loads and normalises the normal of one pixel. Returns 1 when the pixel renders, 0 when the
// normal is too short, -1 when it is not finite.
int sh_load_normal(SH_GLOBAL const float* normal, int n, int p, int pixels, float* unit,
                   float* length) {
  const float x = normal[(n * 3 + 0) * pixels + p];
  const float y = normal[(n * 3 + 1) * pixels + p];
  const float z = normal[(n * 3 + 2) * pixels + p];
  const float len = SH_SQRT(x * x + y * y + z * z);
  *length = len;
  if (!SH_ISFINITE(len)) return -1;
  if (len < SH_MIN_NORMAL_LENGTH) return 0;
  unit[0] = x / len;
  unit[1] = y / len;
  unit[2] = z / len;
  return 1;
}

// e_i = sum_jk T_ijk v_j c_k over the sparse table.
void sh_visible_cosine(SH_GLOBAL const float* table, int table_count, const float* v,
                       const float* c, float* e) {
  for (int i = 0; i < SH_COEFFS; ++i) e[i] = 0.0f;
  for (int t = 0; t < table_count; ++t) {
    const int i = (int)table[4 * t], j = (int)table[4 * t + 1], k = (int)table[4 * t + 2];
    e[i] += table[4 * t + 3] * v[j] * c[k];
  }
}

void sh_forward_item(int item, SH_GLOBAL const float* albedo, SH_GLOBAL const float* normal,
                     SH_GLOBAL const float* visibility, SH_GLOBAL const float* light,
                     SH_GLOBAL const float* mask, SH_GLOBAL const float* table,
                     SH_GLOBAL float* image, SH_GLOBAL float* shading, SH_GLOBAL float* invalid,
                     int has_mask, int table_count, int pixels) {
  const int n = item / pixels, p = item - n * pixels;
  float unit[3], len;
  int state = 0;
  if (!has_mask || mask[n * pixels + p] > 0.5f) state = sh_load_normal(normal, n, p, pixels, unit, &len);
  invalid[item] = state < 0 ? 1.0f : 0.0f;
  if (state <= 0) {
    for (int ch = 0; ch < 3; ++ch) {
      image[(n * 3 + ch) * pixels + p] = 0.0f;
      shading[(n * 3 + ch) * pixels + p] = 0.0f;
    }
    return;
  }
  float c[SH_COEFFS], v[SH_COEFFS], e[SH_COEFFS];
  sh_cosine_coeffs(unit[0], unit[1], unit[2], c);
  for (int j = 0; j < SH_COEFFS; ++j) v[j] = visibility[(n * SH_COEFFS + j) * pixels + p];
  sh_visible_cosine(table, table_count, v, c, e);
  for (int ch = 0; ch < 3; ++ch) {
    float s = 0.0f;
    for (int i = 0; i < SH_COEFFS; ++i) s += light[n * 27 + ch * SH_COEFFS + i] * e[i];
    s *= SH_INV_PI;
    shading[(n * 3 + ch) * pixels + p] = s;
    image[(n * 3 + ch) * pixels + p] = albedo[(n * 3 + ch) * pixels + p] * s;
  }
}

// Flags of sh_backward_item: which incoming gradients exist and which outputs are wanted.
#define SH_HAS_D_IMAGE 1
#define SH_HAS_D_SHADING 2
#define SH_WANT_ALBEDO 4
#define SH_WANT_NORMAL 8
#define SH_WANT_VISIBILITY 16
#define SH_WANT_LIGHT 32
#define SH_ACCUMULATE_ALBEDO 64
#define SH_ACCUMULATE_NORMAL 128
#define SH_ACCUMULATE_VISIBILITY 256

void sh_store(SH_GLOBAL float* out, int index, float value, int accumulate) {
  out[index] = accumulate ? out[index] + value : value;
}

// Per-pixel gradients to albedo, normal and visibility; for the light it writes the pixel's
// d(loss)/d(shading) (ds [N,3,P]) and e (e_out [N,9,P]), summed later by sh_light_partial_item.
void sh_backward_item(int item, SH_GLOBAL const float* albedo, SH_GLOBAL const float* normal,
                      SH_GLOBAL const float* visibility, SH_GLOBAL const float* light,
                      SH_GLOBAL const float* mask, SH_GLOBAL const float* table,
                      SH_GLOBAL const float* d_image, SH_GLOBAL const float* d_shading,
                      SH_GLOBAL float* d_albedo, SH_GLOBAL float* d_normal,
                      SH_GLOBAL float* d_visibility, SH_GLOBAL float* ds_out,
                      SH_GLOBAL float* e_out, int has_mask, int table_count, int pixels,
                      int flags) {
  const int n = item / pixels, p = item - n * pixels;
  float unit[3], len = 0.0f;
  int state = 0;
  if (!has_mask || mask[n * pixels + p] > 0.5f) state = sh_load_normal(normal, n, p, pixels, unit, &len);
  float c[SH_COEFFS], v[SH_COEFFS], e[SH_COEFFS], ds[3], da[3], de[SH_COEFFS], dv[SH_COEFFS],
      dc[SH_COEFFS], dn[3];
  for (int i = 0; i < SH_COEFFS; ++i) {
    c[i] = 0.0f; v[i] = 0.0f; e[i] = 0.0f; dv[i] = 0.0f; dc[i] = 0.0f; de[i] = 0.0f;
  }
  for (int a = 0; a < 3; ++a) { ds[a] = 0.0f; da[a] = 0.0f; dn[a] = 0.0f; }
  if (state > 0) {
    sh_cosine_coeffs(unit[0], unit[1], unit[2], c);
    for (int j = 0; j < SH_COEFFS; ++j) v[j] = visibility[(n * SH_COEFFS + j) * pixels + p];
    sh_visible_cosine(table, table_count, v, c, e);
    for (int ch = 0; ch < 3; ++ch) {
      const int at = (n * 3 + ch) * pixels + p;
      float s = 0.0f;
      for (int i = 0; i < SH_COEFFS; ++i) s += light[n * 27 + ch * SH_COEFFS + i] * e[i];
      s *= SH_INV_PI;
      const float g_image = (flags & SH_HAS_D_IMAGE) ? d_image[at] : 0.0f;
      const float g_shading = (flags & SH_HAS_D_SHADING) ? d_shading[at] : 0.0f;
      ds[ch] = g_image * albedo[at] + g_shading;
      da[ch] = g_image * s;
      for (int i = 0; i < SH_COEFFS; ++i)
        de[i] += SH_INV_PI * ds[ch] * light[n * 27 + ch * SH_COEFFS + i];
    }
    if (flags & (SH_WANT_NORMAL | SH_WANT_VISIBILITY)) {
      for (int t = 0; t < table_count; ++t) {
        const int i = (int)table[4 * t], j = (int)table[4 * t + 1], k = (int)table[4 * t + 2];
        dv[j] += table[4 * t + 3] * de[i] * c[k];
        dc[k] += table[4 * t + 3] * de[i] * v[j];
      }
    }
    if (flags & SH_WANT_NORMAL) {
      float g[3 * SH_COEFFS], du[3] = {0.0f, 0.0f, 0.0f};
      sh_cosine_coeffs_gradient(unit[0], unit[1], unit[2], g);
      for (int k = 0; k < SH_COEFFS; ++k)
        for (int a = 0; a < 3; ++a) du[a] += dc[k] * g[3 * k + a];
      // Through the normalisation: dn = (du - n^ (n^ . du)) / |n|.
      const float radial = du[0] * unit[0] + du[1] * unit[1] + du[2] * unit[2];
      for (int a = 0; a < 3; ++a) dn[a] = (du[a] - unit[a] * radial) / len;
    }
  }
  if (flags & SH_WANT_ALBEDO)
    for (int ch = 0; ch < 3; ++ch) sh_store(d_albedo, (n * 3 + ch) * pixels + p, da[ch],
                                         flags & SH_ACCUMULATE_ALBEDO);
  if (flags & SH_WANT_NORMAL)
    for (int a = 0; a < 3; ++a) sh_store(d_normal, (n * 3 + a) * pixels + p, dn[a], flags & SH_ACCUMULATE_NORMAL);
  if (flags & SH_WANT_VISIBILITY)
    for (int j = 0; j < SH_COEFFS; ++j)
      sh_store(d_visibility, (n * SH_COEFFS + j) * pixels + p, dv[j],
               flags & SH_ACCUMULATE_VISIBILITY);
  if (flags & SH_WANT_LIGHT) {
    for (int ch = 0; ch < 3; ++ch) ds_out[(n * 3 + ch) * pixels + p] = ds[ch];
    for (int i = 0; i < SH_COEFFS; ++i) e_out[(n * SH_COEFFS + i) * pixels + p] = e[i];
  }
}

// dL[n, ch, i] partial sums: item = row * chunks + q with row = n * 27 + ch * 9 + i sums
// (1/pi) ds[n,ch,p] e[n,i,p] over pixels p in [q * chunk, (q + 1) * chunk) into partial[item].
void sh_light_partial_item(int item, SH_GLOBAL const float* ds, SH_GLOBAL const float* e,
                           SH_GLOBAL float* partial, int pixels, int chunk, int chunks) {
  const int row = item / chunks, q = item - row * chunks;
  const int n = row / 27, ch = (row - n * 27) / SH_COEFFS, i = row - n * 27 - ch * SH_COEFFS;
  const int begin = q * chunk;
  const int end = begin + chunk < pixels ? begin + chunk : pixels;
  float sum = 0.0f;
  for (int p = begin; p < end; ++p)
    sum += ds[(n * 3 + ch) * pixels + p] * e[(n * SH_COEFFS + i) * pixels + p];
  partial[item] = SH_INV_PI * sum;
}

// Row sums in chunks: item = r * out_cols + q sums src[r, q * chunk .. (q + 1) * chunk) of a
// [rows, cols] array into dst[item] (added to it with accumulate).
void sh_reduce_rows_item(int item, SH_GLOBAL const float* src, SH_GLOBAL float* dst, int cols,
                         int chunk, int out_cols, int accumulate) {
  const int r = item / out_cols, q = item - r * out_cols;
  const int begin = q * chunk;
  const int end = begin + chunk < cols ? begin + chunk : cols;
  float sum = 0.0f;
  for (int k = begin; k < end; ++k) sum += src[r * cols + k];
  sh_store(dst, item, sum, accumulate);
}

#ifdef __OPENCL_VERSION__
__kernel void sh_render_forward(__global const float* albedo, __global const float* normal,
                                __global const float* visibility, __global const float* light,
                                __global const float* mask, __global const float* table,
                                __global float* image, __global float* shading,
                                __global float* invalid, int has_mask, int table_count,
                                int pixels) {
  sh_forward_item((int)get_global_id(0), albedo, normal, visibility, light, mask, table, image,
                  shading, invalid, has_mask, table_count, pixels);
}

__kernel void sh_render_backward(__global const float* albedo, __global const float* normal,
                                 __global const float* visibility, __global const float* light,
                                 __global const float* mask, __global const float* table,
                                 __global const float* d_image, __global const float* d_shading,
                                 __global float* d_albedo, __global float* d_normal,
                                 __global float* d_visibility, __global float* ds_out,
                                 __global float* e_out, int has_mask, int table_count,
                                 int pixels, int flags) {
  sh_backward_item((int)get_global_id(0), albedo, normal, visibility, light, mask, table, d_image,
                   d_shading, d_albedo, d_normal, d_visibility, ds_out, e_out, has_mask,
                   table_count, pixels, flags);
}

__kernel void sh_light_partial(__global const float* ds, __global const float* e,
                               __global float* partial, int pixels, int chunk, int chunks) {
  sh_light_partial_item((int)get_global_id(0), ds, e, partial, pixels, chunk, chunks);
}

__kernel void sh_reduce_rows(__global const float* src, __global float* dst, int cols, int chunk,
                             int out_cols, int accumulate) {
  sh_reduce_rows_item((int)get_global_id(0), src, dst, cols, chunk, out_cols, accumulate);
}
#endif
