// Winograd F(4x4, 3x3) transforms for 3x3 stride-1 "same" convolutions; the GEMMs between them
// run in CLBlast. Tiles are 4x4 output pixels; a chunk holds T tiles (image-major, then tile rows),
// and transformed tensors are [36][channels][T] so the 36 GEMMs read contiguous matrices.
// Interpolation points 0, 1, -1, 2, -2 and infinity (the matrices of Lavin and Gray).

// o = B^T d over 6 values read with stride s.
void input_1d(const float* d, int s, float* o, int os) {
  o[0 * os] = 4.0f * d[0] - 5.0f * d[2 * s] + d[4 * s];
  o[1 * os] = -4.0f * (d[s] + d[2 * s]) + d[3 * s] + d[4 * s];
  o[2 * os] = 4.0f * (d[s] - d[2 * s]) - d[3 * s] + d[4 * s];
  o[3 * os] = 2.0f * (d[3 * s] - d[s]) - d[2 * s] + d[4 * s];
  o[4 * os] = 2.0f * (d[s] - d[3 * s]) - d[2 * s] + d[4 * s];
  o[5 * os] = 4.0f * d[s] - 5.0f * d[3 * s] + d[5 * s];
}

// o = A^T m: 6 -> 4.
void output_1d(const float* m, int s, float* o, int os) {
  const float sum12 = m[s] + m[2 * s], diff12 = m[s] - m[2 * s];
  const float sum34 = m[3 * s] + m[4 * s], diff34 = m[3 * s] - m[4 * s];
  o[0 * os] = m[0] + sum12 + sum34;
  o[1 * os] = diff12 + 2.0f * diff34;
  o[2 * os] = sum12 + 4.0f * sum34;
  o[3 * os] = diff12 + 8.0f * diff34 + m[5 * s];
}

// o = A d: 4 -> 6 (the adjoint of output_1d).
void output_adjoint_1d(const float* d, int s, float* o, int os) {
  const float even = d[0] + 4.0f * d[2 * s], odd = 2.0f * d[s] + 8.0f * d[3 * s];
  o[0 * os] = d[0];
  o[1 * os] = d[0] + d[s] + d[2 * s] + d[3 * s];
  o[2 * os] = d[0] - d[s] + d[2 * s] - d[3 * s];
  o[3 * os] = even + odd;
  o[4 * os] = even - odd;
  o[5 * os] = d[3 * s];
}

// o = G g: 3 -> 6.
void weight_1d(const float* g, int s, float* o, int os) {
  o[0 * os] = g[0] * 0.25f;
  o[1 * os] = -(g[0] + g[s] + g[2 * s]) / 6.0f;
  o[2 * os] = -(g[0] - g[s] + g[2 * s]) / 6.0f;
  o[3 * os] = g[0] / 24.0f + g[s] / 12.0f + g[2 * s] / 6.0f;
  o[4 * os] = g[0] / 24.0f - g[s] / 12.0f + g[2 * s] / 6.0f;
  o[5 * os] = g[2 * s];
}

// o = G^T u: 6 -> 3 (the adjoint of weight_1d).
void weight_adjoint_1d(const float* u, int s, float* o, int os) {
  o[0 * os] = u[0] * 0.25f - (u[s] + u[2 * s]) / 6.0f + (u[3 * s] + u[4 * s]) / 24.0f;
  o[1 * os] = (u[2 * s] - u[s]) / 6.0f + (u[3 * s] - u[4 * s]) / 12.0f;
  o[2 * os] = (u[3 * s] + u[4 * s] - u[s] - u[2 * s]) / 6.0f + u[5 * s];
}

// u[xi][o][i] = (G w G^T)[xi] for the convolution with O outputs and I inputs. flipped: the
// weights are those of the convolution's input gradient, w'[o][i] = w[i][o] rotated by 180 degrees
// (w stored [I][O][3][3]). 2-D range (I, O).
__kernel void winograd_weights(__global const float* w, __global float* u, int O, int I,
                               int flipped) {
  const int i = get_global_id(0);
  const int o = get_global_id(1);
  float g[9];
  for (int t = 0; t < 9; ++t)
    g[t] = flipped ? w[(i * O + o) * 9 + 8 - t] : w[(o * I + i) * 9 + t];
  float once[18];  // (G g)[row][kx]
  for (int kx = 0; kx < 3; ++kx) weight_1d(g + kx, 3, once + kx, 3);
  float full[36];
  for (int row = 0; row < 6; ++row) weight_1d(once + row * 3, 1, full + row * 6, 1);
  for (int xi = 0; xi < 36; ++xi) u[(xi * O + o) * I + i] = full[xi];
}

// The image, tile row and tile column of chunk tile t (chunk starting at image n0).
int4 tile_position(int t, int n0, int tiles_x, int tiles_per_image) {
  const int n = n0 + t / tiles_per_image;
  const int local_tile = t % tiles_per_image;
  return (int4)(n, local_tile / tiles_x, local_tile % tiles_x, 0);
}

// v[xi][c][t] = (B^T d B)[xi] for the 6x6 input patch d of tile t, channel c (zero padding).
// 2-D range (T, C).
__kernel void winograd_input(__global const float* x, __global float* v, int n0, int T, int C,
                             int H, int W, int tiles_x, int tiles_per_image) {
  const int t = get_global_id(0);
  const int c = get_global_id(1);
  const int4 p = tile_position(t, n0, tiles_x, tiles_per_image);
  const int iy0 = p.y * 4 - 1, ix0 = p.z * 4 - 1;
  __global const float* plane = x + ((size_t)p.x * C + c) * H * W;
  float d[36];
  for (int py = 0; py < 6; ++py) {
    const int iy = iy0 + py;
    for (int px = 0; px < 6; ++px) {
      const int ix = ix0 + px;
      d[py * 6 + px] = (iy >= 0 && iy < H && ix >= 0 && ix < W) ? plane[iy * W + ix] : 0.0f;
    }
  }
  float once[36];
  for (int px = 0; px < 6; ++px) input_1d(d + px, 6, once + px, 6);
  float full[36];
  for (int row = 0; row < 6; ++row) input_1d(once + row * 6, 1, full + row * 6, 1);
  for (int xi = 0; xi < 36; ++xi) v[((size_t)xi * C + c) * T + t] = full[xi];
}

// y[n, o, 4 ty + a, 4 tx + b] (+)= (A^T m A)[a][b] (+ bias[o]) for tile t, clipped to the image.
// 2-D range (T, O).
__kernel void winograd_output(__global const float* m, __global float* y,
                              __global const float* bias, int has_bias, int accumulate, int n0,
                              int T, int O, int H, int W, int tiles_x, int tiles_per_image) {
  const int t = get_global_id(0);
  const int o = get_global_id(1);
  const int4 p = tile_position(t, n0, tiles_x, tiles_per_image);
  float full[36];
  for (int xi = 0; xi < 36; ++xi) full[xi] = m[((size_t)xi * O + o) * T + t];
  float once[24];  // (A^T m)[a][s]
  for (int s = 0; s < 6; ++s) output_1d(full + s, 6, once + s, 6);
  float tile[16];
  for (int a = 0; a < 4; ++a) output_1d(once + a * 6, 1, tile + a * 4, 1);
  const float b = has_bias ? bias[o] : 0.0f;
  __global float* plane = y + ((size_t)p.x * O + o) * H * W;
  for (int a = 0; a < 4; ++a) {
    const int oy = p.y * 4 + a;
    if (oy >= H) break;
    for (int c = 0; c < 4; ++c) {
      const int ox = p.z * 4 + c;
      if (ox >= W) break;
      const float value = tile[a * 4 + c] + b;
      plane[oy * W + ox] = accumulate ? plane[oy * W + ox] + value : value;
    }
  }
}

// m[xi][o][t] = (A g A^T)[xi] for the 4x4 output-gradient tile g of tile t (zero past the edge).
// 2-D range (T, O).
__kernel void winograd_output_gradient(__global const float* dy, __global float* m, int n0,
                                       int T, int O, int H, int W, int tiles_x,
                                       int tiles_per_image) {
  const int t = get_global_id(0);
  const int o = get_global_id(1);
  const int4 p = tile_position(t, n0, tiles_x, tiles_per_image);
  __global const float* plane = dy + ((size_t)p.x * O + o) * H * W;
  float g[16];
  for (int a = 0; a < 4; ++a) {
    const int oy = p.y * 4 + a;
    for (int c = 0; c < 4; ++c) {
      const int ox = p.z * 4 + c;
      g[a * 4 + c] = (oy < H && ox < W) ? plane[oy * W + ox] : 0.0f;
    }
  }
  float once[24];  // (A g)[row][c]
  for (int c = 0; c < 4; ++c) output_adjoint_1d(g + c, 4, once + c, 4);
  float full[36];
  for (int row = 0; row < 6; ++row) output_adjoint_1d(once + row * 4, 1, full + row * 6, 1);
  for (int xi = 0; xi < 36; ++xi) m[((size_t)xi * O + o) * T + t] = full[xi];
}

// dw[o][i] (+)= G^T s[.][o][i] G, where s[xi][o][i] holds the products summed over all tiles.
// 2-D range (I, O).
__kernel void winograd_weight_gradient(__global const float* s, __global float* dw, int O,
                                       int I, int accumulate) {
  const int i = get_global_id(0);
  const int o = get_global_id(1);
  float full[36];
  for (int xi = 0; xi < 36; ++xi) full[xi] = s[(xi * O + o) * I + i];
  float once[18];  // (G^T s)[ky][col]
  for (int col = 0; col < 6; ++col) weight_adjoint_1d(full + col, 6, once + col, 6);
  __global float* out = dw + (o * I + i) * 9;
  for (int ky = 0; ky < 3; ++ky) {
    float k[3];
    weight_adjoint_1d(once + ky * 6, 1, k, 1);
    for (int kx = 0; kx < 3; ++kx) out[ky * 3 + kx] = accumulate ? out[ky * 3 + kx] + k[kx] : k[kx];
  }
}
