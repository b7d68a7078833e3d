// Convolution helpers around the GEMM: im2col, col2im, bias and batch (un)packing, channel sums.
// A chunk of G images is unrolled at once: col is [Ci*K*K, G*Ho*Wo] (row r = (ci*K + ky)*K + kx,
// column j = g*Ho*Wo + oy*Wo + ox) and the GEMM output is [Co, G*Ho*Wo].

#define WG 256

// The input value that column-matrix row r (tap (ci, ky, kx)) holds for output pixel (oy, ox) of
// image `image`: x[image, ci, oy*stride - pad + ky, ox*stride - pad + kx], 0 in the padding.
float im2col_value(__global const float* x, int image, int r, int oy, int ox, int Ci, int H,
                   int W, int K, int stride, int pad) {
  const int kx = r % K;
  const int ky = (r / K) % K;
  const int ci = r / (K * K);
  const int iy = oy * stride - pad + ky;
  const int ix = ox * stride - pad + kx;
  if (iy < 0 || iy >= H || ix < 0 || ix >= W) return 0.0f;
  return x[((image * Ci + ci) * H + iy) * W + ix];
}

// col[r, j] for j = g*Ho*Wo + oy*Wo + ox.
// 3-D range (Wo, G*Ho, Ci*K*K): the index arithmetic of dimensions 1 and 2 is shared by a row.
__kernel void im2col(__global const float* x, __global float* col, int n0, int G, int Ci, int H,
                     int W, int K, int stride, int pad, int Ho, int Wo) {
  const int ox = get_global_id(0);
  const int gy = get_global_id(1);
  const int r = get_global_id(2);
  const int g = gy / Ho;
  const int oy = gy - g * Ho;
  col[(r * G + g) * Ho * Wo + oy * Wo + ox] =
      im2col_value(x, n0 + g, r, oy, ox, Ci, H, W, K, stride, pad);
}

// The transposed column matrix colT[j, r] = col[r, j] ([G*Ho*Wo, Ci*K*K]) for the weight
// gradient dW = dY colT, which CLBlast then reads without a transposing copy of its own.
// 2-D range (Ci*K*K, G*Ho*Wo): consecutive work-items write consecutive entries of a row (a
// 16x16 local-memory tile transpose, tried on PoCL, ran at half the speed).
__kernel void im2col_transposed(__global const float* x, __global float* col_t, int n0, int G,
                                int Ci, int H, int W, int K, int stride, int pad, int Ho,
                                int Wo) {
  const int r = get_global_id(0);
  const int j = get_global_id(1);
  const int plane_out = Ho * Wo;
  const int g = j / plane_out;
  const int pixel = j - g * plane_out;
  const int oy = pixel / Wo;
  const int ox = pixel - oy * Wo;
  col_t[j * (Ci * K * K) + r] = im2col_value(x, n0 + g, r, oy, ox, Ci, H, W, K, stride, pad);
}

// dx[n0 + g, ci, iy, ix] (+)= sum of the col entries that im2col copied from that pixel.
// 3-D range (W, G*H, Ci).
__kernel void col2im(__global const float* col, __global float* dx, int n0, int G, int Ci, int H,
                     int W, int K, int stride, int pad, int Ho, int Wo, int accumulate) {
  const int ix = get_global_id(0);
  const int gy = get_global_id(1);
  const int ci = get_global_id(2);
  const int g = gy / H;
  const int iy = gy - g * H;
  const int plane_out = Ho * Wo;
  const int cols = G * plane_out;
  float sum = 0.0f;
  for (int ky = 0; ky < K; ++ky) {
    const int ty = iy + pad - ky;
    if (ty < 0) break;
    int oy = ty;
    if (stride != 1) {
      if (ty % stride != 0) continue;
      oy = ty / stride;
    }
    if (oy >= Ho) continue;
    __global const float* row = col + (ci * K + ky) * K * cols + g * plane_out + oy * Wo;
    for (int kx = 0; kx < K; ++kx) {
      const int tx = ix + pad - kx;
      if (tx < 0) break;
      int ox = tx;
      if (stride != 1) {
        if (tx % stride != 0) continue;
        ox = tx / stride;
      }
      if (ox < Wo) sum += row[kx * cols + ox];
    }
  }
  const int o = (((n0 + g) * Ci + ci) * H + iy) * W + ix;
  dx[o] = accumulate ? dx[o] + sum : sum;
}

// y[n0 + g, co, p] = tmp[co, g*plane + p] (+ bias[co]); 2-D range (plane, G*Co).
__kernel void unpack_batch(__global const float* tmp, __global float* y,
                           __global const float* bias, int has_bias, int n0, int G, int Co,
                           int plane) {
  const int p = get_global_id(0);
  const int gc = get_global_id(1);
  const int g = gc / Co;
  const int co = gc - g * Co;
  float v = tmp[(co * G + g) * plane + p];
  if (has_bias) v += bias[co];
  y[(n0 * Co + gc) * plane + p] = v;
}

// tmp[co, g*plane + p] = dy[n0 + g, co, p]; 2-D range (plane, G*Co).
__kernel void pack_batch(__global const float* dy, __global float* tmp, int n0, int G, int Co,
                         int plane) {
  const int p = get_global_id(0);
  const int gc = get_global_id(1);
  const int g = gc / Co;
  const int co = gc - g * Co;
  tmp[(co * G + g) * plane + p] = dy[(n0 * Co + gc) * plane + p];
}

// y[b, c, p] += bias[c]; 2-D range (plane, batch*C).
__kernel void add_channel_bias(__global float* y, __global const float* bias, int C, int plane) {
  const int p = get_global_id(0);
  const int bc = get_global_id(1);
  y[bc * plane + p] += bias[bc % C];
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
