// Synchronised batch norm: host forward and backward with per-channel sums over every rank.
#include "core/autograd/synced_batch_norm.h"

#include <cmath>

#include "core/util/error.h"
#include "core/util/vector_clones.h"

namespace facetool::ag {
namespace {

StatisticsSum& installed_sum() {
  static StatisticsSum sum;
  return sum;
}

// Writes `values` into a gradient target, adding to what it holds when it accumulates.
void write_target(const GradTarget& t, std::vector<float> values) {
  if (!t) return;
  if (t.accumulate) {
    const std::vector<float> old = t.tensor->to_host();
    for (size_t i = 0; i < values.size(); ++i) values[i] += old[i];
  }
  t.tensor->copy_from_host(values);
}

// y = x * a + shift per channel, each product and sum rounded on its own like the cpu backend's
// batch norm (FACETOOL_NO_FP_CONTRACT on both), so that one process gives the same floats
// either way: a value one rounding apart can cross the leaky ReLU's kink that follows.
FACETOOL_NO_FP_CONTRACT
std::vector<float> normalized(const std::vector<float>& x, const Shape& s,
                              const std::vector<float>& gamma, const std::vector<float>& beta,
                              const std::vector<float>& mean, const std::vector<float>& invstd) {
  const int64_t n = s.n(), channels = s.c(), plane = s.h() * s.w();
  std::vector<float> y(x.size());
  for (int64_t i = 0; i < n; ++i)
    for (int64_t c = 0; c < channels; ++c) {
      const float a = gamma[c] * invstd[c], shift = beta[c] - mean[c] * a;
      for (int64_t k = 0; k < plane; ++k) {
        const int64_t at = (i * channels + c) * plane + k;
        y[at] = x[at] * a + shift;
      }
    }
  return y;
}

}  // namespace

void set_batch_norm_statistics_sum(StatisticsSum sum) { installed_sum() = std::move(sum); }
const StatisticsSum& batch_norm_statistics_sum() { return installed_sum(); }

Variable synced_batch_norm(const Variable& x, const Variable& gamma, const Variable& beta,
                           const Tensor& running_mean, const Tensor& running_var,
                           const BatchNormParams& p, const StatisticsSum& sum) {
  const Shape& s = x.value().shape();
  check(s.rank() == 4, "batch_norm: x must be NCHW, got ", s.str());
  const int64_t n = s.n(), channels = s.c(), plane = s.h() * s.w();
  const std::vector<float> xh = x.value().to_host(), g = gamma.value().to_host(),
                           b = beta.value().to_host();
  // Pass 1: global count and mean; pass 2: squared deviations around the global mean (rounded
  // to float), each squared exactly in double: the cpu backend's arithmetic (cpu_batchnorm.cpp),
  // so that both round to the same float statistics.
  std::vector<double> totals(channels + 1, 0.0);
  for (int64_t i = 0; i < n; ++i)
    for (int64_t c = 0; c < channels; ++c)
      for (int64_t k = 0; k < plane; ++k) totals[c] += xh[(i * channels + c) * plane + k];
  totals[channels] = static_cast<double>(n * plane);
  sum(totals);
  const double count = totals[channels];
  check(count > 1, "batch_norm: training mode needs more than one value per channel over all "
        "ranks, got ", count);
  std::vector<double> squares(channels, 0.0);
  std::vector<float> mean(channels), invstd(channels);
  for (int64_t c = 0; c < channels; ++c) mean[c] = static_cast<float>(totals[c] / count);
  for (int64_t i = 0; i < n; ++i)
    for (int64_t c = 0; c < channels; ++c)
      for (int64_t k = 0; k < plane; ++k) {
        const double d = xh[(i * channels + c) * plane + k] - mean[c];
        squares[c] += d * d;
      }
  sum(squares);
  std::vector<float> rm = running_mean.to_host(), rv = running_var.to_host();
  for (int64_t c = 0; c < channels; ++c) {
    invstd[c] = static_cast<float>(1.0 / std::sqrt(squares[c] / count + p.eps));
    rm[c] = (1.0f - p.momentum) * rm[c] + p.momentum * mean[c];
    rv[c] = (1.0f - p.momentum) * rv[c] +
            p.momentum * static_cast<float>(squares[c] / (count - 1.0));
  }
  running_mean.copy_from_host(rm);
  running_var.copy_from_host(rv);
  Tensor yt = Tensor::from_host(x.value().backend(), s, normalized(xh, s, g, b, mean, invstd));
  return make_result(
      yt, "synced_batch_norm", {x, gamma, beta},
      [xh, g, mean, invstd, s, sum](const Tensor& grad, const std::vector<GradTarget>& t) {
        const int64_t n = s.n(), channels = s.c(), plane = s.h() * s.w();
        const std::vector<float> dy = grad.to_host();
        std::vector<double> sums(2 * channels + 1, 0.0);  // sum(dy), sum(dy * xhat), count
        for (int64_t i = 0; i < n; ++i)
          for (int64_t c = 0; c < channels; ++c)
            for (int64_t k = 0; k < plane; ++k) {
              const int64_t at = (i * channels + c) * plane + k;
              sums[c] += dy[at];
              sums[channels + c] += dy[at] * static_cast<double>((xh[at] - mean[c]) * invstd[c]);
            }
        sums[2 * channels] = static_cast<double>(n * plane);
        std::vector<float> dgamma(channels), dbeta(channels);
        for (int64_t c = 0; c < channels; ++c) {
          dbeta[c] = static_cast<float>(sums[c]);
          dgamma[c] = static_cast<float>(sums[channels + c]);
        }
        sum(sums);
        const double count = sums[2 * channels];
        if (t[0]) {
          std::vector<float> dx(dy.size());
          for (int64_t i = 0; i < n; ++i)
            for (int64_t c = 0; c < channels; ++c) {
              const float scale = g[c] * invstd[c];
              const float mean_dy = static_cast<float>(sums[c] / count);
              const float mean_dy_xhat = static_cast<float>(sums[channels + c] / count);
              const float k_c = invstd[c] * mean_dy_xhat;  // grouped as on the cpu backend
              for (int64_t k = 0; k < plane; ++k) {
                const int64_t at = (i * channels + c) * plane + k;
                dx[at] = scale * (dy[at] - mean_dy - (xh[at] - mean[c]) * k_c);
              }
            }
          write_target(t[0], std::move(dx));
        }
        write_target(t[1], std::move(dgamma));
        write_target(t[2], std::move(dbeta));
      });
}

}  // namespace facetool::ag
