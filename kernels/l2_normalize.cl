// Per-pixel L2 normalisation over channels: y = x / max(||x||, eps), and its gradient.

// One work-item per pixel of x [batch, C, plane]: 2-D range (plane, batch).
__kernel void l2_normalize(__global const float* x, __global float* y, float eps, int C,
                           int plane) {
  const int base = get_global_id(1) * C * plane + get_global_id(0);
  float sq = 0.0f;
  for (int c = 0; c < C; ++c) {
    const float v = x[base + c * plane];
    sq += v * v;
  }
  const float norm = sqrt(sq);
  const float denom = norm < eps ? eps : norm;  // keeps NaN, unlike fmax
  for (int c = 0; c < C; ++c) y[base + c * plane] = x[base + c * plane] / denom;
}

// Where ||x|| >= eps: dx = (dy - y (y . dy)) / ||x||; below eps the denominator is the constant
// eps: dx = dy / eps.
__kernel void l2_normalize_backward(__global const float* x, __global const float* dy,
                                    __global float* dx, float eps, int accumulate, int C,
                                    int plane) {
  const int base = get_global_id(1) * C * plane + get_global_id(0);
  float sq = 0.0f;
  float xdy = 0.0f;
  for (int c = 0; c < C; ++c) {
    const float v = x[base + c * plane];
    sq += v * v;
    xdy += v * dy[base + c * plane];
  }
  const float norm = sqrt(sq);
  const int clamped = norm < eps;
  const float inv = 1.0f / (clamped ? eps : norm);
  const float proj = clamped ? 0.0f : xdy * inv * inv;  // (x . dy) / ||x||^2
  for (int c = 0; c < C; ++c) {
    const int k = base + c * plane;
    const float g = (dy[k] - x[k] * proj) * inv;
    dx[k] = accumulate ? dx[k] + g : g;
  }
}
