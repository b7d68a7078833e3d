// SGEMM selection: oneDNN's sgemm by default (its JIT kernels follow the CPU's features and ran
// the convolution GEMMs ~10-20% faster than OpenBLAS here); FACETOOL_GEMM=openblas|dnnl overrides.
#include <cstdlib>
#include <string>

#include "backends/cpu/gemm.h"
#include "backends/cpu/gemm_dnnl.h"
#include "backends/cpu/gemm_openblas.h"
#include "core/util/error.h"

namespace facetool::cpu {
namespace {

enum class GemmLibrary { OpenBlas, Dnnl };

struct GemmChoice {
  GemmLibrary library;
  std::string reason;
};

GemmChoice choose_library() {
  openblas_prepare();
  if (const char* env = std::getenv("FACETOOL_GEMM")) {
    const std::string wanted = env;
    if (wanted == "openblas") return {GemmLibrary::OpenBlas, "set by FACETOOL_GEMM"};
    if (wanted == "dnnl") return {GemmLibrary::Dnnl, "set by FACETOOL_GEMM"};
    if (!wanted.empty())
      fail("FACETOOL_GEMM='", wanted, "' is not a known GEMM library; use openblas or dnnl");
  }
  return {GemmLibrary::Dnnl, "default; FACETOOL_GEMM=openblas for OpenBLAS " +
                                openblas_core_name() + " kernels"};
}

const GemmChoice& choice() {
  static const GemmChoice chosen = choose_library();
  return chosen;
}

GemmLibrary library() { return choice().library; }

}  // namespace

void sgemm(bool trans_a, bool trans_b, int64_t m, int64_t n, int64_t k, float alpha,
           const float* a, int64_t lda, const float* b, int64_t ldb, float beta, float* c,
           int64_t ldc) {
  if (m <= 0 || n <= 0) return;
  if (library() == GemmLibrary::Dnnl)
    dnnl_single_thread_sgemm(trans_a, trans_b, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
  else
    openblas_sgemm(trans_a, trans_b, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
}

std::string sgemm_description() {
  const char* name = library() == GemmLibrary::Dnnl ? "oneDNN sgemm" : "OpenBLAS sgemm";
  return std::string(name) + " (" + choice().reason + ")";
}

}  // namespace facetool::cpu
