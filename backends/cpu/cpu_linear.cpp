// The fully connected layer on the cpu: y = x w^T + b and its gradients through SGEMM.
#include <algorithm>

#include "backends/cpu/cpu_backend_impl.h"
#include "backends/cpu/gemm.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {
namespace {

// Rows per task: a few tasks per thread, but not so few rows that the GEMM calls get tiny.
int64_t row_grain(int64_t rows) {
  return std::max<int64_t>(8, rows / (4 * parallel_thread_count()));
}

}  // namespace

void CpuBackend::linear(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y) {
  const int64_t batch = x.shape()[0];
  const int64_t in = x.shape()[1];
  const int64_t out = w.shape()[0];
  const float* px = ptr(x);
  const float* pw = ptr(w);
  const float* pb = bias ? ptr(*bias) : nullptr;
  float* py = ptr(y);
  // One product per sample: a GEMM library may sum a lone row (a matrix-vector product) in
  // another order than rows of a larger batch, and a sample's output must not depend on the
  // batch it came in (a photo gives the same bytes alone or among others, sharded or not).
  // The weights are small next to the batch's activations, so this costs little.
  parallel_for(batch, row_grain(batch), [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i)
      sgemm(false, true, 1, out, in, 1.0f, px + i * in, in, pw, in, 0.0f, py + i * out, out);
    if (pb)
      for (int64_t i = begin; i < end; ++i)
        for (int64_t o = 0; o < out; ++o) py[i * out + o] += pb[o];
  });
}

void CpuBackend::linear_backward(const Tensor& x, const Tensor& w, const Tensor& dy,
                                 const Tensor* dx, const Tensor* dw, const Tensor* dbias,
                                 bool accumulate) {
  const int64_t batch = x.shape()[0];
  const int64_t in = x.shape()[1];
  const int64_t out = w.shape()[0];
  const float* px = ptr(x);
  const float* pw = ptr(w);
  const float* pdy = ptr(dy);
  const float beta = accumulate ? 1.0f : 0.0f;
  if (dx) {
    // dx [N, in] = dy [N, out] * w [out, in], split over rows of dx.
    float* pdx = ptr(*dx);
    parallel_for(batch, row_grain(batch), [&](int64_t begin, int64_t end) {
      sgemm(false, false, end - begin, in, out, 1.0f, pdy + begin * out, out, pw, in, beta,
            pdx + begin * in, in);
    });
  }
  if (dw) {
    // dw [out, in] = dy^T [out, N] * x [N, in], split over rows of dw.
    float* pdw = ptr(*dw);
    parallel_for(out, row_grain(out), [&](int64_t begin, int64_t end) {
      sgemm(true, false, end - begin, in, batch, 1.0f, pdy + begin, out, px, in, beta,
            pdw + begin * in, in);
    });
  }
  if (dbias) {
    float* pdb = ptr(*dbias);
    for (int64_t o = 0; o < out; ++o) {
      float total = 0.0f;
      for (int64_t i = 0; i < batch; ++i) total += pdy[i * out + o];
      store(pdb[o], total, accumulate);
    }
  }
}

}  // namespace facetool::cpu
