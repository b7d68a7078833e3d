// Both SGEMM libraries of the cpu backend (oneDNN, OpenBLAS) against a double-precision loop.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "backends/cpu/gemm.h"
#include "backends/cpu/gemm_dnnl.h"
#include "backends/cpu/gemm_openblas.h"

namespace facetool::cpu {
namespace {

using GemmFn = void (*)(bool, bool, int64_t, int64_t, int64_t, float, const float*, int64_t,
                        const float*, int64_t, float, float*, int64_t);

struct Case {
  int64_t m, n, k;
};

// Checks C = alpha op(A) op(B) + beta C for every transposition, with padded leading
// dimensions, against the double-precision sum; the bound is 1e-5 times the sum of |terms|.
void check_gemm(GemmFn gemm, const char* name) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  for (const Case& c : {Case{1, 1, 1}, Case{3, 5, 7}, Case{33, 65, 17}, Case{128, 448, 300}})
    for (int trans = 0; trans < 4; ++trans)
      for (float beta : {0.0f, 1.0f}) {
        const bool ta = trans & 1, tb = trans & 2;
        const int64_t a_rows = ta ? c.k : c.m, a_cols = ta ? c.m : c.k;
        const int64_t b_rows = tb ? c.n : c.k, b_cols = tb ? c.k : c.n;
        const int64_t lda = a_cols + 3, ldb = b_cols + 1, ldc = c.n + 2;
        std::vector<float> a(a_rows * lda), b(b_rows * ldb), out(c.m * ldc);
        for (float& v : a) v = uniform(rng);
        for (float& v : b) v = uniform(rng);
        for (float& v : out) v = uniform(rng);
        // With beta == 0 the old contents must be ignored, even NaN.
        if (beta == 0.0f) out[0] = std::numeric_limits<float>::quiet_NaN();
        const std::vector<float> before = out;
        const float alpha = 0.75f;
        gemm(ta, tb, c.m, c.n, c.k, alpha, a.data(), lda, b.data(), ldb, beta, out.data(), ldc);
        for (int64_t i = 0; i < c.m; ++i)
          for (int64_t j = 0; j < c.n; ++j) {
            double sum = 0.0, magnitude = 0.0;
            for (int64_t p = 0; p < c.k; ++p) {
              const double av = ta ? a[p * lda + i] : a[i * lda + p];
              const double bv = tb ? b[j * ldb + p] : b[p * ldb + j];
              sum += av * bv;
              magnitude += std::abs(av * bv);
            }
            const double expected = alpha * sum + (beta != 0.0f ? before[i * ldc + j] : 0.0);
            ASSERT_NEAR(out[i * ldc + j], expected, 1e-5 * (magnitude + 1.0))
                << name << " m=" << c.m << " n=" << c.n << " k=" << c.k << " trans_a=" << ta
                << " trans_b=" << tb << " beta=" << beta << " at (" << i << ", " << j << ")";
          }
        // Padding columns of C stay untouched.
        for (int64_t i = 0; i < c.m; ++i)
          for (int64_t j = c.n; j < ldc; ++j) ASSERT_EQ(out[i * ldc + j], before[i * ldc + j]);
      }
}

TEST(CpuGemm, OneDnnMatchesDoubleLoop) { check_gemm(&dnnl_single_thread_sgemm, "oneDNN"); }

TEST(CpuGemm, OpenBlasMatchesDoubleLoop) {
  openblas_prepare();
  check_gemm(&openblas_sgemm, "OpenBLAS");
}

TEST(CpuGemm, DefaultIsDescribed) {
  EXPECT_NE(sgemm_description().find("sgemm"), std::string::npos) << sgemm_description();
}

}  // namespace
}  // namespace facetool::cpu
