// Adam on the cpu, the update rule of torch.optim.Adam (L2 weight decay, no amsgrad).
#include <algorithm>
#include <cmath>
#include <vector>

#include "backends/cpu/cpu_backend_impl.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {

namespace {

// The update of elements [begin, end) of one parameter.
void adam_range(float* pp, const float* pg, float* pm, float* pv, int64_t begin, int64_t end,
                const AdamParams& p, float step_size, float bias_correction2_sqrt) {
  for (int64_t i = begin; i < end; ++i) {
    const float g = pg[i] + p.weight_decay * pp[i];
    pm[i] = p.beta1 * pm[i] + (1.0f - p.beta1) * g;
    pv[i] = p.beta2 * pv[i] + (1.0f - p.beta2) * g * g;
    const float denom = std::sqrt(pv[i]) / bias_correction2_sqrt + p.eps;
    pp[i] -= step_size * pm[i] / denom;
  }
}

struct AdamScalars {
  float step_size, bias_correction2_sqrt;
  explicit AdamScalars(const AdamParams& p) {
    const double t = static_cast<double>(p.step);
    const float bias_correction1 = static_cast<float>(1.0 - std::pow(double(p.beta1), t));
    bias_correction2_sqrt = static_cast<float>(std::sqrt(1.0 - std::pow(double(p.beta2), t)));
    step_size = p.lr / bias_correction1;
  }
};

}  // namespace

void CpuBackend::adam_step(const Tensor& param, const Tensor& grad, const Tensor& m,
                           const Tensor& v, const AdamParams& p) {
  const AdamScalars s(p);
  parallel_for(param.numel(), kElementwiseGrain, [&](int64_t begin, int64_t end) {
    adam_range(ptr(param), ptr(grad), ptr(m), ptr(v), begin, end, p, s.step_size,
               s.bias_correction2_sqrt);
  });
}

void CpuBackend::adam_step_all(const std::vector<AdamTensors>& tensors, const AdamParams& p) {
  // All parameters laid end to end as one index range, cut into chunks that may span several
  // parameters: one parallel loop (one barrier) for the whole step. Every element gets the
  // same arithmetic as adam_step, so the values are identical.
  const AdamScalars s(p);
  std::vector<int64_t> starts(tensors.size() + 1, 0);
  for (size_t k = 0; k < tensors.size(); ++k)
    starts[k + 1] = starts[k] + tensors[k].param.numel();
  parallel_for(starts.back(), kElementwiseGrain, [&](int64_t begin, int64_t end) {
    size_t k = static_cast<size_t>(
        std::upper_bound(starts.begin(), starts.end(), begin) - starts.begin() - 1);
    for (; k < tensors.size() && starts[k] < end; ++k) {
      const AdamTensors& t = tensors[k];
      const int64_t lo = std::max(begin, starts[k]) - starts[k];
      const int64_t hi = std::min(end, starts[k + 1]) - starts[k];
      adam_range(ptr(t.param), ptr(t.grad), ptr(t.m), ptr(t.v), lo, hi, p, s.step_size,
                 s.bias_correction2_sqrt);
    }
  });
}

}  // namespace facetool::cpu
