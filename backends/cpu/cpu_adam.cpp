// Adam on the cpu, the update rule of torch.optim.Adam (L2 weight decay, no amsgrad).
#include <cmath>

#include "backends/cpu/cpu_backend_impl.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {

void CpuBackend::adam_step(const Tensor& param, const Tensor& grad, const Tensor& m,
                           const Tensor& v, const AdamParams& p) {
  float* pp = ptr(param);
  const float* pg = ptr(grad);
  float* pm = ptr(m);
  float* pv = ptr(v);
  const double t = static_cast<double>(p.step);
  const float bias_correction1 = static_cast<float>(1.0 - std::pow(double(p.beta1), t));
  const float bias_correction2_sqrt =
      static_cast<float>(std::sqrt(1.0 - std::pow(double(p.beta2), t)));
  const float step_size = p.lr / bias_correction1;
  parallel_for(param.numel(), kElementwiseGrain, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const float g = pg[i] + p.weight_decay * pp[i];
      pm[i] = p.beta1 * pm[i] + (1.0f - p.beta1) * g;
      pv[i] = p.beta2 * pv[i] + (1.0f - p.beta2) * g * g;
      const float denom = std::sqrt(pv[i]) / bias_correction2_sqrt + p.eps;
      pp[i] -= step_size * pm[i] / denom;
    }
  });
}

}  // namespace facetool::cpu
