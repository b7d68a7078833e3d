// One Adam update (torch.optim.Adam rule, L2 weight decay) of a parameter tensor in place.

// step_size = lr / (1 - beta1^t); bc2_sqrt = sqrt(1 - beta2^t), both computed on the host.
__kernel void adam_step(__global float* param, __global const float* grad, __global float* m,
                        __global float* v, float beta1, float beta2, float eps,
                        float weight_decay, float step_size, float bc2_sqrt, int n) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const float p = param[i];
  const float g = grad[i] + weight_decay * p;
  const float mi = beta1 * m[i] + (1.0f - beta1) * g;
  const float vi = beta2 * v[i] + (1.0f - beta2) * g * g;
  m[i] = mi;
  v[i] = vi;
  param[i] = p - step_size * mi / (sqrt(vi) / bc2_sqrt + eps);
}
