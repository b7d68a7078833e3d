// Whole-tensor sums in two deterministic stages: per-group partial sums, then one group adds them.

#define WG 256

inline float group_total(__local float* scratch, float v) {
  const int l = get_local_id(0);
  scratch[l] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = WG / 2; s > 0; s >>= 1) {
    if (l < s) scratch[l] += scratch[l + s];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  return scratch[0];
}

// partials[group] = sum of x[i] over this group's strided share of [0, n).
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void sum_partials(
    __global const float* x, __global float* partials, int n) {
  __local float scratch[WG];
  float acc = 0.0f;
  for (int i = get_global_id(0); i < n; i += get_global_size(0)) acc += x[i];
  const float total = group_total(scratch, acc);
  if (get_local_id(0) == 0) partials[get_group_id(0)] = total;
}

// y[0] = scale * sum of partials[0, count); launched as one group.
__kernel __attribute__((reqd_work_group_size(WG, 1, 1))) void sum_final(
    __global const float* partials, int count, __global float* y, float scale) {
  __local float scratch[WG];
  float acc = 0.0f;
  for (int i = get_local_id(0); i < count; i += WG) acc += partials[i];
  const float total = group_total(scratch, acc);
  if (get_local_id(0) == 0) y[0] = total * scale;
}
