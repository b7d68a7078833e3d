// Element-wise kernels: fill, copy, channel copies, add/mul/scale/axpy and their gradients.
// Every kernel takes its item count and ignores work-items past it.

__kernel void fill(__global float* y, float value, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] = value;
}

__kernel void copy(__global const float* x, __global float* y, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] = x[i];
}

// y[b, dst_c0 + c, p] (+)= x[b, src_c0 + c, p] for c < count; 2-D range (plane, batch*count).
__kernel void copy_channels(__global const float* x, int x_channels, int src_c0,
                            __global float* y, int y_channels, int dst_c0, int count, int plane,
                            int accumulate) {
  const int p = get_global_id(0);
  const int b = get_global_id(1) / count;
  const int c = get_global_id(1) - b * count;
  const float v = x[(b * x_channels + src_c0 + c) * plane + p];
  const int o = (b * y_channels + dst_c0 + c) * plane + p;
  y[o] = accumulate ? y[o] + v : v;
}

__kernel void add(__global const float* a, __global const float* b, __global float* y, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] = a[i] + b[i];
}

__kernel void mul(__global const float* a, __global const float* b, __global float* y, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] = a[i] * b[i];
}

__kernel void scale(__global const float* x, float alpha, __global float* y, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] = alpha * x[i];
}

__kernel void axpy(float alpha, __global const float* x, __global float* y, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] += alpha * x[i];
}

// dout (+)= dy * other: the gradient of one factor of a product.
__kernel void mul_grad(__global const float* other, __global const float* dy,
                       __global float* dout, int accumulate, int n) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float g = dy[i] * other[i];
  dout[i] = accumulate ? dout[i] + g : g;
}

// dx (+)= dy[0] * scale
__kernel void broadcast_scalar(__global const float* dy, float scale, __global float* dx,
                               int accumulate, int n) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float g = dy[0] * scale;
  dx[i] = accumulate ? dx[i] + g : g;
}
