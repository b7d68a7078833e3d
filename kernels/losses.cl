// Masked mean-squared error: loss = sum(mask (pred - target)^2) / (C sum(mask)), 0 for an empty
// mask. pred/target [batch, C, plane], mask [batch, 1, plane].

#define WG 256

inline float group_total(__local float* scratch, float v) {
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

// partials[g] = this group's share of sum(mask * d^2); partials[groups + g] = of sum(mask).
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void masked_mse_partials(
    __global const float* pred, __global const float* target, __global const float* mask,
    __global float* partials, int C, int plane, int n_pred, int n_mask) {
  __local float scratch[WG];
  float err = 0.0f;
  for (int i = get_global_id(0); i < n_pred; i += get_global_size(0)) {
    const float d = pred[i] - target[i];
    err += mask[(i / (C * plane)) * plane + i % plane] * d * d;
  }
  float msum = 0.0f;
  for (int i = get_global_id(0); i < n_mask; i += get_global_size(0)) msum += mask[i];
  const float e = group_total(scratch, err);
  const float m = group_total(scratch, msum);
  if (get_local_id(0) == 0) {
    partials[get_group_id(0)] = e;
    partials[get_num_groups(0) + get_group_id(0)] = m;
  }
}

// result[0] = loss, result[1] = sum(mask); launched as one group.
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void masked_mse_final(
    __global const float* partials, int groups, int C, __global float* loss,
    __global float* mask_sum) {
  __local float scratch[WG];
  float e = 0.0f;
  float m = 0.0f;
  for (int i = get_local_id(0); i < groups; i += WG) {
    e += partials[i];
    m += partials[groups + i];
  }
  const float err = group_total(scratch, e);
  const float msum = group_total(scratch, m);
  if (get_local_id(0) == 0) {
    loss[0] = msum == 0.0f ? 0.0f : err / ((float)C * msum);
    mask_sum[0] = msum;
  }
}

// g = dloss * 2 mask (pred - target) / (C sum(mask)); dpred (+)= g, dtarget (+)= -g.
// 2-D range (plane, batch*C).
__kernel void masked_mse_backward(__global const float* pred, __global const float* target,
                                  __global const float* mask, __global const float* dloss,
                                  __global const float* mask_sum, __global float* dpred,
                                  int want_dpred, __global float* dtarget, int want_dtarget,
                                  int accumulate, int C, int plane) {
  const int p = get_global_id(0);
  const int i = get_global_id(1) * plane + p;
  const float msum = mask_sum[0];
  float g = 0.0f;
  if (msum != 0.0f) {
    const float m = mask[(get_global_id(1) / C) * plane + p];
    g = dloss[0] * 2.0f * m * (pred[i] - target[i]) / ((float)C * msum);
  }
  if (want_dpred) dpred[i] = accumulate ? dpred[i] + g : g;
  if (want_dtarget) dtarget[i] = accumulate ? dtarget[i] - g : -g;
}
