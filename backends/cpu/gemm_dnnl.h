// Single-threaded SGEMM through oneDNN's dnnl_sgemm (its JIT picks AVX-512 where available).
#pragma once

#include <cstdint>

namespace facetool::cpu {

void dnnl_single_thread_sgemm(bool trans_a, bool trans_b, int64_t m, int64_t n, int64_t k,
                              float alpha, const float* a, int64_t lda, const float* b,
                              int64_t ldb, float beta, float* c, int64_t ldc);

}  // namespace facetool::cpu
