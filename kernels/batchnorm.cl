// Batch normalisation: per-channel statistics (one work-group per channel, local tree
// reductions), the normalisation itself, and the backward pass.

#define WG 256

// Sum of v over the work-group; every work-item gets the result.
inline float group_sum(__local float* scratch, float v) {
  const int l = get_local_id(0);
  scratch[l] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = WG / 2; s > 0; s >>= 1) {
    if (l < s) scratch[l] += scratch[l + s];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  const float total = scratch[0];
  barrier(CLK_LOCAL_MEM_FENCE);
  return total;
}

#define CHANNEL_INDEX(idx) (((idx) / plane * C + c) * plane + (idx) % plane)

// Training: batch mean and biased variance (two passes), running statistics updated with the
// unbiased variance. Eval: the running statistics. Writes what it normalises with.
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void bn_statistics(
    __global const float* x, int batch, int C, int plane, __global float* running_mean,
    __global float* running_var, __global float* save_mean, __global float* save_invstd,
    float momentum, float eps, int training) {
  __local float scratch[WG];
  const int c = get_group_id(0);
  const int l = get_local_id(0);
  if (!training) {
    if (l == 0) {
      save_mean[c] = running_mean[c];
      save_invstd[c] = 1.0f / sqrt(running_var[c] + eps);
    }
    return;
  }
  const int count = batch * plane;
  float acc = 0.0f;
  for (int idx = l; idx < count; idx += WG) acc += x[CHANNEL_INDEX(idx)];
  const float mean = group_sum(scratch, acc) / (float)count;
  acc = 0.0f;
  for (int idx = l; idx < count; idx += WG) {
    const float d = x[CHANNEL_INDEX(idx)] - mean;
    acc += d * d;
  }
  const float var = group_sum(scratch, acc) / (float)count;
  if (l == 0) {
    save_mean[c] = mean;
    save_invstd[c] = 1.0f / sqrt(var + eps);
    const float unbiased = count > 1 ? var * (float)count / (float)(count - 1) : var;
    running_mean[c] = (1.0f - momentum) * running_mean[c] + momentum * mean;
    running_var[c] = (1.0f - momentum) * running_var[c] + momentum * unbiased;
  }
}

// y = (x - mean) * invstd * gamma + beta; 2-D range (plane, batch*C).
__kernel void bn_apply(__global const float* x, __global const float* mean,
                       __global const float* invstd, __global const float* gamma,
                       __global const float* beta, __global float* y, int C, int plane) {
  const int c = get_global_id(1) % C;
  const int i = get_global_id(1) * plane + get_global_id(0);
  const float scale = invstd[c] * gamma[c];
  y[i] = (x[i] - mean[c]) * scale + beta[c];
}

// sums[c] = sum dy, sums[C + c] = sum dy * xhat; dgamma/dbeta (+)= those when wanted.
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void bn_backward_reduce(
    __global const float* x, __global const float* dy, __global const float* mean,
    __global const float* invstd, int batch, int C, int plane, __global float* sums,
    __global float* dgamma, int want_dgamma, __global float* dbeta, int want_dbeta,
    int accumulate) {
  __local float scratch[WG];
  const int c = get_group_id(0);
  const int l = get_local_id(0);
  const int count = batch * plane;
  const float m = mean[c];
  const float s = invstd[c];
  float acc_dy = 0.0f;
  float acc_dyx = 0.0f;
  for (int idx = l; idx < count; idx += WG) {
    const int k = CHANNEL_INDEX(idx);
    const float g = dy[k];
    acc_dy += g;
    acc_dyx += g * (x[k] - m) * s;
  }
  const float sum_dy = group_sum(scratch, acc_dy);
  const float sum_dyx = group_sum(scratch, acc_dyx);
  if (l == 0) {
    sums[c] = sum_dy;
    sums[C + c] = sum_dyx;
    if (want_dgamma) dgamma[c] = accumulate ? dgamma[c] + sum_dyx : sum_dyx;
    if (want_dbeta) dbeta[c] = accumulate ? dbeta[c] + sum_dy : sum_dy;
  }
}

// Training: dx = gamma*invstd*(dy - sum_dy/M - xhat*sum_dyxhat/M); eval: dx = dy*gamma*invstd.
// 2-D range (plane, batch*C).
__kernel void bn_backward_dx(__global const float* x, __global const float* dy,
                             __global const float* mean, __global const float* invstd,
                             __global const float* gamma, __global const float* sums,
                             __global float* dx, int training, int accumulate, int C, int plane,
                             int count) {
  const int c = get_global_id(1) % C;
  const int i = get_global_id(1) * plane + get_global_id(0);
  const float s = invstd[c];
  float g;
  if (training) {
    const float xhat = (x[i] - mean[c]) * s;
    const float inv_count = 1.0f / (float)count;
    g = gamma[c] * s * (dy[i] - sums[c] * inv_count - xhat * sums[C + c] * inv_count);
  } else {
    g = dy[i] * gamma[c] * s;
  }
  dx[i] = accumulate ? dx[i] + g : g;
}
