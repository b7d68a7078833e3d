// Row-major single-precision GEMM through CLBlast, with per-device-type tuning overrides.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <functional>
#include <memory>

#include "backends/opencl/opencl_context.h"

namespace facetool::opencl {

// A device buffer borrowed from the backend's cache for the duration of one call.
struct ScratchBuffer {
  cl_mem mem = nullptr;
  std::shared_ptr<void> owner;  // returns the block to the cache when released
};
using ScratchAllocator = std::function<ScratchBuffer(size_t bytes)>;

// Applies the tuning-table entry for this device's type to CLBlast (once per device). CPU
// devices (PoCL) get parameters measured on this project's machines; other devices keep
// CLBlast's own database. FACETOOL_CLBLAST_DEFAULTS=1 skips the overrides;
// FACETOOL_CLBLAST_XGEMM="NAME=VALUE,..." adds Xgemm parameters on any device (checked once).
// Returns a short description of what was applied.
std::string apply_clblast_tuning(const Context& context);

class Gemm {
 public:
  Gemm(const Context& context, ScratchAllocator scratch);

  // C[m, n] = alpha * op(A) op(B) + beta * C, all row-major with leading dimensions lda/ldb/ldc
  // and element offsets. op(X) = X^T when trans_x. beta == 0 never reads C.
  void run(bool trans_a, bool trans_b, size_t m, size_t n, size_t k, float alpha, cl_mem a,
           size_t a_offset, size_t lda, cl_mem b, size_t b_offset, size_t ldb, float beta,
           cl_mem c, size_t c_offset, size_t ldc);

  const std::string& tuning() const { return tuning_; }

 private:
  // Runs two GEMMs against a host reference; fails when the tuning computes wrong results.
  void self_check();

  const Context& context_;
  ScratchAllocator scratch_;
  std::string tuning_;
};

}  // namespace facetool::opencl
