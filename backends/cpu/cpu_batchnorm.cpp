// Batch normalisation on the cpu (PyTorch semantics), one channel per task.
#include <cmath>
#include <cstring>

#include "backends/cpu/cpu_backend_impl.h"
#include "core/util/parallel_for.h"
#include "core/util/vector_clones.h"

namespace facetool::cpu {
namespace {

// Visits every value of channel c of an NCHW tensor: fn(pointer to the (n, c) plane, plane size).
template <typename Fn>
void for_each_plane(const Shape& s, int64_t c, const float* base, Fn fn) {
  const int64_t plane = s.h() * s.w();
  for (int64_t n = 0; n < s.n(); ++n) fn(base + (n * s.c() + c) * plane, plane);
}

// sum(term(v[i])) over a plane in double, in 8 independent lanes so it vectorises. `term` returns
// a double computed from float inputs as the host batch norm does (synced_batch_norm.cpp), so
// that both give the same statistics after rounding to float.
template <typename Term>
double lane_sum(const float* v, int64_t m, Term term) {
  constexpr int kLanes = 8;
  double lanes[kLanes] = {};
  int64_t i = 0;
  for (; i + kLanes <= m; i += kLanes)
    for (int l = 0; l < kLanes; ++l) lanes[l] += term(v[i + l]);
  double total = 0.0;
  for (; i < m; ++i) total += term(v[i]);
  for (double lane : lanes) total += lane;
  return total;
}

// out = in * a + b, then the leaky ReLU of `slope` when `leaky` (in and out never overlap). The
// product and the sum are rounded separately (no fused multiply-add, whatever the clone), as in
// the host batch norm: a result one rounding apart can sit on the other side of the leaky ReLU's
// kink, and one such pixel changes the step's gradient by 1e-3 (docs/distributed.md).
FACETOOL_VECTOR_CLONES FACETOOL_NO_FP_CONTRACT
void affine_plane(const float* __restrict in, int64_t m, float a, float b, bool leaky,
                  float slope, float* __restrict out) {
  if (leaky) {
    FACETOOL_NO_ALIAS_LOOP
    for (int64_t i = 0; i < m; ++i) {
      const float v = in[i] * a + b;
      out[i] = v > 0.0f ? v : slope * v;
    }
  } else {
    FACETOOL_NO_ALIAS_LOOP
    for (int64_t i = 0; i < m; ++i) out[i] = in[i] * a + b;
  }
}

// The batch norm, followed by a leaky ReLU of `slope` when `leaky`, in the same pass.
void normalize(const Tensor& x, const Tensor& gamma, const Tensor& beta,
               const Tensor& running_mean, const Tensor& running_var, const Tensor& save_mean,
               const Tensor& save_invstd, const Tensor& y, const BatchNormParams& p, bool leaky,
               float slope) {
  const Shape& s = x.shape();
  const int64_t count = s.n() * s.h() * s.w();
  const int64_t plane = s.h() * s.w();
  const float* px = ptr(x);
  float* py = ptr(y);
  const float* pg = ptr(gamma);
  const float* pbeta = ptr(beta);
  float* prm = ptr(running_mean);
  float* prv = ptr(running_var);
  float* psm = ptr(save_mean);
  float* psi = ptr(save_invstd);
  parallel_for(s.c(), 1, [&](int64_t begin, int64_t end) {
    for (int64_t c = begin; c < end; ++c) {
      float mean, invstd;
      if (p.training) {
        // Two passes in double: the mean, then the biased variance around its float value
        // (each deviation rounded to float, squared exactly in double).
        double total = 0.0;
        for_each_plane(s, c, px, [&](const float* v, int64_t m) {
          total += lane_sum(v, m, [](float a) { return static_cast<double>(a); });
        });
        const double batch_mean = total / static_cast<double>(count);
        double squares = 0.0;
        const float centre = static_cast<float>(batch_mean);
        for_each_plane(s, c, px, [&](const float* v, int64_t m) {
          squares += lane_sum(v, m, [centre](float a) {
            const double d = a - centre;
            return d * d;
          });
        });
        const double biased_var = squares / static_cast<double>(count);
        const double unbiased_var = squares / static_cast<double>(count - 1);
        mean = static_cast<float>(batch_mean);
        invstd = static_cast<float>(1.0 / std::sqrt(biased_var + p.eps));
        prm[c] = (1.0f - p.momentum) * prm[c] + p.momentum * mean;
        prv[c] = (1.0f - p.momentum) * prv[c] + p.momentum * static_cast<float>(unbiased_var);
      } else {
        mean = prm[c];
        invstd = 1.0f / std::sqrt(prv[c] + p.eps);
      }
      psm[c] = mean;
      psi[c] = invstd;
      const float a = pg[c] * invstd;
      const float b = pbeta[c] - mean * a;
      for (int64_t n = 0; n < s.n(); ++n) {
        const int64_t o = (n * s.c() + c) * plane;
        affine_plane(px + o, plane, a, b, leaky, slope, py + o);
      }
    }
  });
}

// One plane's sum(g) and sum(g * xhat), g = dy, times the leaky ReLU's derivative read from the
// activation's output `a` (nullptr: none), in 8 double lanes so the loops vectorise. xhat is
// rounded to float and the product taken exactly in double, as in the host batch norm.
FACETOOL_VECTOR_CLONES
void plane_sums(const float* __restrict in, const float* __restrict dy,
                const float* __restrict a, int64_t m, float mean, float invstd, float slope,
                double& sum_dy, double& sum_dy_xhat) {
  constexpr int kLanes = 8;
  double lanes_dy[kLanes] = {}, lanes_dy_xhat[kLanes] = {};
  const int64_t whole = m / kLanes * kLanes;
  if (a) {
    // The activation's derivative selected for a block of 8 values at once (a vector select,
    // GCC's vector extension): written per value, GCC compiled it to a compare and a branch per
    // value, mispredicted about half the time, 16 % of a training step on an AVX2 machine.
    typedef float Floats8 __attribute__((vector_size(kLanes * sizeof(float))));
    for (int64_t i = 0; i < whole; i += kLanes) {
      Floats8 d, act;
      std::memcpy(&d, dy + i, sizeof d);
      std::memcpy(&act, a + i, sizeof act);
      const Floats8 selected = act > 0.0f ? d : d * slope;
      float g[kLanes];
      std::memcpy(g, &selected, sizeof g);
      for (int l = 0; l < kLanes; ++l) {
        const float xhat = (in[i + l] - mean) * invstd;
        lanes_dy[l] += g[l];
        lanes_dy_xhat[l] += static_cast<double>(g[l]) * xhat;
      }
    }
  } else {
    for (int64_t i = 0; i < whole; i += kLanes)
      for (int l = 0; l < kLanes; ++l) {
        const float xhat = (in[i + l] - mean) * invstd;
        lanes_dy[l] += dy[i + l];
        lanes_dy_xhat[l] += static_cast<double>(dy[i + l]) * xhat;
      }
  }
  double total_dy = 0.0, total_dy_xhat = 0.0;
  for (int64_t i = whole; i < m; ++i) {
    const float g = !a || a[i] > 0.0f ? dy[i] : slope * dy[i];
    const float xhat = (in[i] - mean) * invstd;
    total_dy += g;
    total_dy_xhat += static_cast<double>(g) * xhat;
  }
  for (int l = 0; l < kLanes; ++l) {
    total_dy += lanes_dy[l];
    total_dy_xhat += lanes_dy_xhat[l];
  }
  sum_dy += total_dy;
  sum_dy_xhat += total_dy_xhat;
}

// One plane of dx (+)= scale * (g - mean_dy - xhat * mean_dy_xhat), g as in plane_sums.
FACETOOL_VECTOR_CLONES
void plane_dx(const float* __restrict in, const float* __restrict dy, const float* __restrict a,
              int64_t m, float mean, float invstd, float slope, float scale, float mean_dy,
              float mean_dy_xhat, bool accumulate, float* __restrict out) {
  const float k = invstd * mean_dy_xhat;
  if (a && accumulate) {
    FACETOOL_NO_ALIAS_LOOP
    for (int64_t i = 0; i < m; ++i)
      out[i] += scale * ((a[i] > 0.0f ? dy[i] : slope * dy[i]) - mean_dy - (in[i] - mean) * k);
  } else if (a) {
    FACETOOL_NO_ALIAS_LOOP
    for (int64_t i = 0; i < m; ++i)
      out[i] = scale * ((a[i] > 0.0f ? dy[i] : slope * dy[i]) - mean_dy - (in[i] - mean) * k);
  } else if (accumulate) {
    FACETOOL_NO_ALIAS_LOOP
    for (int64_t i = 0; i < m; ++i) out[i] += scale * (dy[i] - mean_dy - (in[i] - mean) * k);
  } else {
    FACETOOL_NO_ALIAS_LOOP
    for (int64_t i = 0; i < m; ++i) out[i] = scale * (dy[i] - mean_dy - (in[i] - mean) * k);
  }
}

// The batch norm's backward; with `activated` (the output of the fused leaky ReLU of `slope`),
// dy is first multiplied by the activation's derivative, element by element as it is read.
void normalize_backward(const Tensor& x, const Tensor& gamma, const Tensor& save_mean,
                        const Tensor& save_invstd, const Tensor& dy, const Tensor* activated,
                        float slope, const Tensor* dx, const Tensor* dgamma, const Tensor* dbeta,
                        const BatchNormParams& p, bool accumulate) {
  const Shape& s = x.shape();
  const int64_t count = s.n() * s.h() * s.w();
  const int64_t plane = s.h() * s.w();
  const float* px = ptr(x);
  const float* pdy = ptr(dy);
  const float* pg = ptr(gamma);
  const float* psm = ptr(save_mean);
  const float* psi = ptr(save_invstd);
  float* pdx = dx ? ptr(*dx) : nullptr;
  float* pdg = dgamma ? ptr(*dgamma) : nullptr;
  float* pdb = dbeta ? ptr(*dbeta) : nullptr;
  const float* pa = activated ? ptr(*activated) : nullptr;
  parallel_for(s.c(), 1, [&](int64_t begin, int64_t end) {
    for (int64_t c = begin; c < end; ++c) {
      const float mean = psm[c];
      const float invstd = psi[c];
      // sum(dy) and sum(dy * xhat) over the channel.
      double sum_dy = 0.0, sum_dy_xhat = 0.0;
      for (int64_t n = 0; n < s.n(); ++n) {
        const int64_t offset = (n * s.c() + c) * plane;
        plane_sums(px + offset, pdy + offset, pa ? pa + offset : nullptr, plane, mean, invstd,
                   slope, sum_dy, sum_dy_xhat);
      }
      if (pdb) store(pdb[c], static_cast<float>(sum_dy), accumulate);
      if (pdg) store(pdg[c], static_cast<float>(sum_dy_xhat), accumulate);
      if (!pdx) continue;
      const float scale = pg[c] * invstd;
      // Training: dx = gamma*invstd * (dy - mean(dy) - xhat * mean(dy * xhat)).
      const float mean_dy = p.training ? static_cast<float>(sum_dy / count) : 0.0f;
      const float mean_dy_xhat = p.training ? static_cast<float>(sum_dy_xhat / count) : 0.0f;
      for (int64_t n = 0; n < s.n(); ++n) {
        const int64_t o = (n * s.c() + c) * plane;
        plane_dx(px + o, pdy + o, pa ? pa + o : nullptr, plane, mean, invstd, slope, scale,
                 mean_dy, mean_dy_xhat, accumulate, pdx + o);
      }
    }
  });
}

}  // namespace

void CpuBackend::batch_norm(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                            const Tensor& running_mean, const Tensor& running_var,
                            const Tensor& save_mean, const Tensor& save_invstd, const Tensor& y,
                            const BatchNormParams& p) {
  normalize(x, gamma, beta, running_mean, running_var, save_mean, save_invstd, y, p, false, 0.0f);
}

bool CpuBackend::batch_norm_leaky_relu(const Tensor& x, const Tensor& gamma, const Tensor& beta,
                                       const Tensor& running_mean, const Tensor& running_var,
                                       const Tensor& save_mean, const Tensor& save_invstd,
                                       float slope, const Tensor& y, const BatchNormParams& p) {
  normalize(x, gamma, beta, running_mean, running_var, save_mean, save_invstd, y, p, true, slope);
  return true;
}

void CpuBackend::batch_norm_backward(const Tensor& x, const Tensor& gamma,
                                     const Tensor& save_mean, const Tensor& save_invstd,
                                     const Tensor& dy, const Tensor* dx, const Tensor* dgamma,
                                     const Tensor* dbeta, const BatchNormParams& p,
                                     bool accumulate) {
  normalize_backward(x, gamma, save_mean, save_invstd, dy, nullptr, 0.0f, dx, dgamma, dbeta, p,
                     accumulate);
}

bool CpuBackend::batch_norm_leaky_relu_backward(const Tensor& x, const Tensor& gamma,
                                                const Tensor& save_mean,
                                                const Tensor& save_invstd, const Tensor& y,
                                                float slope, const Tensor& dy, const Tensor* dx,
                                                const Tensor* dgamma, const Tensor* dbeta,
                                                const BatchNormParams& p, bool accumulate) {
  normalize_backward(x, gamma, save_mean, save_invstd, dy, &y, slope, dx, dgamma, dbeta, p,
                     accumulate);
  return true;
}

}  // namespace facetool::cpu
