// Activation kernels: leaky ReLU and sigmoid, forward and backward.

__kernel void leaky_relu(__global const float* x, float slope, __global float* y, int n) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float v = x[i];
  y[i] = v > 0.0f ? v : v * slope;
}

// dx (+)= dy * (x > 0 ? 1 : slope)
__kernel void leaky_relu_backward(__global const float* x, float slope, __global const float* dy,
                                  __global float* dx, int accumulate, int n) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float g = x[i] > 0.0f ? dy[i] : dy[i] * slope;
  dx[i] = accumulate ? dx[i] + g : g;
}

__kernel void sigmoid(__global const float* x, __global float* y, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] = 1.0f / (1.0f + exp(-x[i]));
}

// dx (+)= dy * y * (1 - y)
__kernel void sigmoid_backward(__global const float* y, __global const float* dy,
                               __global float* dx, int accumulate, int n) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float s = y[i];
  const float g = dy[i] * s * (1.0f - s);
  dx[i] = accumulate ? dx[i] + g : g;
}
