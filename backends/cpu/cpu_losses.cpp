// Sum, scalar broadcast (the backward of sum and mean) and the masked MSE loss on the cpu.
#include <vector>

#include "backends/cpu/cpu_backend_impl.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {
namespace {

// Sum of term(i) over [0, n) in double, with a fixed chunking so results do not depend on
// which thread ran what.
template <typename Term>
double parallel_sum(int64_t n, Term term) {
  constexpr int64_t kChunk = 65536;
  const int64_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<double> partial(static_cast<size_t>(chunks), 0.0);
  parallel_for(chunks, 1, [&](int64_t begin, int64_t end) {
    for (int64_t c = begin; c < end; ++c) {
      double total = 0.0;
      const int64_t stop = std::min(n, (c + 1) * kChunk);
      for (int64_t i = c * kChunk; i < stop; ++i) total += term(i);
      partial[static_cast<size_t>(c)] = total;
    }
  });
  double total = 0.0;
  for (double v : partial) total += v;
  return total;
}

}  // namespace

void CpuBackend::sum(const Tensor& x, const Tensor& y) {
  const float* px = ptr(x);
  ptr(y)[0] = static_cast<float>(parallel_sum(x.numel(), [=](int64_t i) { return px[i]; }));
}

void CpuBackend::broadcast_scalar_backward(const Tensor& dy, float scale, const Tensor& dx,
                                           bool accumulate) {
  const float g = ptr(dy)[0] * scale;
  float* pdx = ptr(dx);
  parallel_for(dx.numel(), kElementwiseGrain, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) store(pdx[i], g, accumulate);
  });
}

void CpuBackend::masked_mse(const Tensor& pred, const Tensor& target, const Tensor& mask,
                            const Tensor& loss) {
  const Shape& s = pred.shape();
  const int64_t plane = s.h() * s.w();
  const float* pp = ptr(pred);
  const float* pt = ptr(target);
  const float* pm = ptr(mask);
  const double mask_total = parallel_sum(mask.numel(), [=](int64_t i) { return pm[i]; });
  const double error = parallel_sum(pred.numel(), [=](int64_t i) {
    const int64_t n = i / (s.c() * plane);
    const double d = double(pp[i]) - double(pt[i]);
    return double(pm[n * plane + i % plane]) * d * d;
  });
  // An empty mask gives 0; a NaN mask total fails the comparison and propagates.
  ptr(loss)[0] = mask_total == 0.0 ? 0.0f
                                   : static_cast<float>(error / (double(s.c()) * mask_total));
}

void CpuBackend::masked_mse_backward(const Tensor& pred, const Tensor& target, const Tensor& mask,
                                     const Tensor& dloss, const Tensor* dpred,
                                     const Tensor* dtarget, bool accumulate) {
  const Shape& s = pred.shape();
  const int64_t plane = s.h() * s.w();
  const float* pp = ptr(pred);
  const float* pt = ptr(target);
  const float* pm = ptr(mask);
  const double mask_total = parallel_sum(mask.numel(), [=](int64_t i) { return pm[i]; });
  // d loss / d pred = 2 * mask * (pred - target) / (C * sum(mask)); zero for an empty mask.
  const float factor =
      mask_total == 0.0 ? 0.0f
                        : static_cast<float>(2.0 * ptr(dloss)[0] / (double(s.c()) * mask_total));
  float* pdp = dpred ? ptr(*dpred) : nullptr;
  float* pdt = dtarget ? ptr(*dtarget) : nullptr;
  parallel_for(pred.numel(), kElementwiseGrain, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const int64_t n = i / (s.c() * plane);
      const float g = mask_total == 0.0 ? 0.0f : factor * pm[n * plane + i % plane] * (pp[i] - pt[i]);
      if (pdp) store(pdp[i], g, accumulate);
      if (pdt) store(pdt[i], -g, accumulate);
    }
  });
}

}  // namespace facetool::cpu
