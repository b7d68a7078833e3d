// Single-threaded SGEMM through OpenBLAS's cblas interface.
#pragma once

#include <cstdint>
#include <string>

namespace facetool::cpu {

// Switches OpenBLAS to one thread per call (facetool threads around it) and reports its core.
void openblas_prepare();
std::string openblas_core_name();
void openblas_sgemm(bool trans_a, bool trans_b, int64_t m, int64_t n, int64_t k, float alpha,
                    const float* a, int64_t lda, const float* b, int64_t ldb, float beta,
                    float* c, int64_t ldc);

}  // namespace facetool::cpu
