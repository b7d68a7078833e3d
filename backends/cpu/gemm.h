// The cpu backend's single SGEMM entry point; which library computes it is decided in gemm.cpp.
#pragma once

#include <cstdint>
#include <string>

namespace facetool::cpu {

// Row-major C = alpha * op(A) * op(B) + beta * C with op(A) [m, k], op(B) [k, n], C [m, n].
// Runs on the calling thread only (the backend parallelises around it with parallel_for), so
// it may be called concurrently from several threads. With beta == 0, C is overwritten (old
// contents, even NaN, are ignored).
void sgemm(bool trans_a, bool trans_b, int64_t m, int64_t n, int64_t k, float alpha,
           const float* a, int64_t lda, const float* b, int64_t ldb, float beta, float* c,
           int64_t ldc);

// Which implementation sgemm uses, e.g. "OpenBLAS (SkylakeX kernels)".
std::string sgemm_description();

}  // namespace facetool::cpu
