// oneDNN SGEMM, limited to the calling thread (oneDNN's OpenMP team is set to one thread).
#include "backends/cpu/gemm_dnnl.h"

#include <dnnl.h>
#include <omp.h>

#include "core/util/error.h"

namespace facetool::cpu {

void dnnl_single_thread_sgemm(bool trans_a, bool trans_b, int64_t m, int64_t n, int64_t k,
                              float alpha, const float* a, int64_t lda, const float* b,
                              int64_t ldb, float beta, float* c, int64_t ldc) {
  // OpenMP's thread count is per calling thread: set it once on each thread that gets here.
  thread_local const bool single = (omp_set_num_threads(1), true);
  (void)single;
  const dnnl_status_t status = dnnl_sgemm(trans_a ? 'T' : 'N', trans_b ? 'T' : 'N', m, n, k,
                                          alpha, a, lda, b, ldb, beta, c, ldc);
  check(status == dnnl_success, "oneDNN sgemm failed with status ", static_cast<int>(status),
        " (m=", m, ", n=", n, ", k=", k, ")");
}

}  // namespace facetool::cpu
