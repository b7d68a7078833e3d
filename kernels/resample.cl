// Resampling and pooling: bilinear 2x upsampling (align_corners=False) and global average pooling.

#define WG 256

// Output index o of a 2x upsampling reads inputs i0 (weight w0) and i1 (weight 1 - w0); PyTorch's
// source index (o + 0.5) / 2 - 0.5 clamped at 0.
inline void source_taps(int o, int in_size, int* i0, int* i1, float* w0) {
  float src = ((float)o + 0.5f) * 0.5f - 0.5f;
  if (src < 0.0f) src = 0.0f;
  const int lo = (int)src;
  *i0 = lo;
  *i1 = lo + 1 < in_size ? lo + 1 : in_size - 1;
  *w0 = 1.0f - (src - (float)lo);
}

// Weight of input index i in output index o.
inline float tap_weight(int o, int i, int in_size) {
  int i0, i1;
  float w0;
  source_taps(o, in_size, &i0, &i1, &w0);
  return (i0 == i ? w0 : 0.0f) + (i1 == i ? 1.0f - w0 : 0.0f);
}

// x [planes, H, W] -> y [planes, 2H, 2W]; 3-D range (2W, 2H, planes).
__kernel void upsample_bilinear2x(__global const float* x, __global float* y, int H, int W) {
  const int Wo = 2 * W;
  const int Ho = 2 * H;
  const int ox = get_global_id(0);
  const int oy = get_global_id(1);
  const int plane = get_global_id(2);
  const int i = (plane * Ho + oy) * Wo + ox;
  int y0, y1, x0, x1;
  float wy, wx;
  source_taps(oy, H, &y0, &y1, &wy);
  source_taps(ox, W, &x0, &x1, &wx);
  __global const float* p = x + plane * H * W;
  y[i] = wy * (wx * p[y0 * W + x0] + (1.0f - wx) * p[y0 * W + x1]) +
         (1.0f - wy) * (wx * p[y1 * W + x0] + (1.0f - wx) * p[y1 * W + x1]);
}

// dx[plane, iy, ix] (+)= sum over the outputs that read it; gathers, so no atomics are needed.
// 3-D range (W, H, planes).
__kernel void upsample_bilinear2x_backward(__global const float* dy, __global float* dx, int H,
                                           int W, int accumulate) {
  const int ix = get_global_id(0);
  const int iy = get_global_id(1);
  const int plane = get_global_id(2);
  const int i = (plane * H + iy) * W + ix;
  const int Wo = 2 * W;
  const int Ho = 2 * H;
  __global const float* g = dy + plane * Ho * Wo;
  float sum = 0.0f;
  for (int oy = max(2 * iy - 2, 0); oy <= min(2 * iy + 3, Ho - 1); ++oy) {
    const float wy = tap_weight(oy, iy, H);
    if (wy == 0.0f) continue;
    float row = 0.0f;
    for (int ox = max(2 * ix - 2, 0); ox <= min(2 * ix + 3, Wo - 1); ++ox) {
      const float wx = tap_weight(ox, ix, W);
      if (wx != 0.0f) row += wx * g[oy * Wo + ox];
    }
    sum += wy * row;
  }
  dx[i] = accumulate ? dx[i] + sum : sum;
}

// y[p] = mean of x[p, :]; one work-group per plane.
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void global_avg_pool(
    __global const float* x, __global float* y, int plane) {
  __local float scratch[WG];
  const int p = get_group_id(0);
  const int l = get_local_id(0);
  float acc = 0.0f;
  for (int k = l; k < plane; k += WG) acc += x[p * plane + k];
  scratch[l] = acc;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = WG / 2; s > 0; s >>= 1) {
    if (l < s) scratch[l] += scratch[l + s];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (l == 0) y[p] = scratch[0] / (float)plane;
}

// dx[p, k] (+)= dy[p] / plane; 2-D range (plane, planes).
__kernel void global_avg_pool_backward(__global const float* dy, __global float* dx, int plane,
                                       int accumulate) {
  const int i = get_global_id(1) * plane + get_global_id(0);
  const float g = dy[get_global_id(1)] / (float)plane;
  dx[i] = accumulate ? dx[i] + g : g;
}
