// Convolution helpers around the GEMM: im2col, col2im, bias and batch (un)packing, channel sums.
// A chunk of G images is unrolled at once: col is [Ci*K*K, G*Ho*Wo] (row r = (ci*K + ky)*K + kx,
// column j = g*Ho*Wo + oy*Wo + ox) and the GEMM output is [Co, G*Ho*Wo].

#define WG 256

// col[r, j] = x[n0 + g, ci, oy*stride - pad + ky, ox*stride - pad + kx] (0 outside the image).
__kernel void im2col(__global const float* x, __global float* col, int n0, int G, int Ci, int H,
                     int W, int K, int stride, int pad, int Ho, int Wo) {
  const int i = get_global_id(0);
  const int plane_out = Ho * Wo;
  const int cols = G * plane_out;
  if (i >= Ci * K * K * cols) return;
  const int j = i % cols;
  const int r = i / cols;
  const int g = j / plane_out;
  const int pix = j - g * plane_out;
  const int oy = pix / Wo;
  const int ox = pix - oy * Wo;
  const int kx = r % K;
  const int ky = (r / K) % K;
  const int ci = r / (K * K);
  const int iy = oy * stride - pad + ky;
  const int ix = ox * stride - pad + kx;
  float v = 0.0f;
  if (iy >= 0 && iy < H && ix >= 0 && ix < W) v = x[(((n0 + g) * Ci + ci) * H + iy) * W + ix];
  col[i] = v;
}

// dx[n0 + g, ci, iy, ix] (+)= sum of the col entries that im2col copied from that pixel.
__kernel void col2im(__global const float* col, __global float* dx, int n0, int G, int Ci, int H,
                     int W, int K, int stride, int pad, int Ho, int Wo, int accumulate) {
  const int i = get_global_id(0);
  if (i >= G * Ci * H * W) return;
  const int ix = i % W;
  const int iy = (i / W) % H;
  const int ci = (i / (W * H)) % Ci;
  const int g = i / (W * H * Ci);
  const int plane_out = Ho * Wo;
  const int cols = G * plane_out;
  float sum = 0.0f;
  for (int ky = 0; ky < K; ++ky) {
    const int ty = iy + pad - ky;
    if (ty < 0 || ty % stride != 0) continue;
    const int oy = ty / stride;
    if (oy >= Ho) continue;
    for (int kx = 0; kx < K; ++kx) {
      const int tx = ix + pad - kx;
      if (tx < 0 || tx % stride != 0) continue;
      const int ox = tx / stride;
      if (ox >= Wo) continue;
      sum += col[((ci * K + ky) * K + kx) * cols + g * plane_out + oy * Wo + ox];
    }
  }
  const int o = ((n0 + g) * Ci + ci) * H * W + iy * W + ix;
  dx[o] = accumulate ? dx[o] + sum : sum;
}

// y[n0 + g, co, p] = tmp[co, g*plane + p] (+ bias[co]).
__kernel void unpack_batch(__global const float* tmp, __global float* y,
                           __global const float* bias, int has_bias, int n0, int G, int Co,
                           int plane) {
  const int i = get_global_id(0);
  if (i >= G * Co * plane) return;
  const int p = i % plane;
  const int co = (i / plane) % Co;
  const int g = i / (plane * Co);
  float v = tmp[(co * G + g) * plane + p];
  if (has_bias) v += bias[co];
  y[n0 * Co * plane + i] = v;
}

// tmp[co, g*plane + p] = dy[n0 + g, co, p]
__kernel void pack_batch(__global const float* dy, __global float* tmp, int n0, int G, int Co,
                         int plane) {
  const int i = get_global_id(0);
  if (i >= G * Co * plane) return;
  const int p = i % plane;
  const int co = (i / plane) % Co;
  const int g = i / (plane * Co);
  tmp[(co * G + g) * plane + p] = dy[n0 * Co * plane + i];
}

// y[b, c, p] += bias[c] over n = batch*C*plane items.
__kernel void add_channel_bias(__global float* y, __global const float* bias, int C, int plane,
                               int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] += bias[(i / plane) % C];
}

// out[c] (+)= sum over b, p of x[b, c, p]; one work-group of WG items per channel.
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void channel_sum(
    __global const float* x, __global float* out, int batch, int C, int plane, int accumulate) {
  __local float scratch[WG];
  const int c = get_group_id(0);
  const int l = get_local_id(0);
  const int count = batch * plane;
  float acc = 0.0f;
  for (int idx = l; idx < count; idx += WG) {
    const int b = idx / plane;
    acc += x[(b * C + c) * plane + (idx - b * plane)];
  }
  scratch[l] = acc;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = WG / 2; s > 0; s >>= 1) {
    if (l < s) scratch[l] += scratch[l + s];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (l == 0) out[c] = accumulate ? out[c] + scratch[0] : scratch[0];
}
