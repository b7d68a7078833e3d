// CLBlast GEMM calls, the scratch buffer CLBlast needs, and the per-device tuning table.
#include "backends/opencl/clblast_gemm.h"

#include <clblast.h>

#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>

#include "core/util/error.h"

namespace facetool::opencl {
namespace {

using Parameters = std::unordered_map<std::string, size_t>;

struct KernelOverride {
  const char* kernel;
  Parameters parameters;
};

// Tuning table by device type. CPU (PoCL): no local memory, an 8x16 register tile and wide
// vectors (~80 GFLOP/s on the convolution's GEMM vs ~16-27 with CLBlast's defaults), and the
// indirect kernel for every size (the direct one stays near 17 GFLOP/s whatever its tuning).
// GPUs: CLBlast's own database.
const std::vector<KernelOverride>& cpu_overrides() {
  static const std::vector<KernelOverride> table = {
      {"Xgemm",
       {{"GEMMK", 0}, {"KWG", 16}, {"KWI", 2}, {"MDIMA", 16}, {"MDIMC", 16}, {"MWG", 128},
        {"NDIMB", 8}, {"NDIMC", 8}, {"NWG", 128}, {"SA", 0}, {"SB", 0}, {"STRM", 0},
        {"STRN", 0}, {"VWM", 8}, {"VWN", 16}}},
      {"GemmRoutine", {{"XGEMM_MIN_INDIRECT_SIZE", 1}}},
  };
  return table;
}

std::string status_text(clblast::StatusCode code) {
  return "CLBlast status " + std::to_string(static_cast<int>(code));
}

}  // namespace

std::string apply_clblast_tuning(const Context& context) {
  static std::mutex mutex;
  static std::map<cl_device_id, std::string> applied;
  std::lock_guard<std::mutex> lock(mutex);
  auto found = applied.find(context.device());
  if (found != applied.end()) return found->second;

  std::string description = "CLBlast defaults";
  const char* env = std::getenv("FACETOOL_CLBLAST_DEFAULTS");
  const bool keep_defaults = env && *env && std::string(env) != "0";
  if (context.is_cpu() && !keep_defaults) {
    for (const KernelOverride& entry : cpu_overrides()) {
      // Start from CLBlast's current values so parameters not in the table (e.g. KREG) stay set.
      Parameters parameters;
      clblast::RetrieveParameters(context.device(), entry.kernel, clblast::Precision::kSingle,
                                  parameters);
      for (const auto& [key, value] : entry.parameters) parameters[key] = value;
      const clblast::StatusCode status = clblast::OverrideParameters(
          context.device(), entry.kernel, clblast::Precision::kSingle, parameters);
      check(status == clblast::StatusCode::kSuccess, "CLBlast: overriding the ", entry.kernel,
            " parameters failed: ", status_text(status));
    }
    description = "CLBlast with the CPU tuning table";
  }
  applied.emplace(context.device(), description);
  return description;
}

Gemm::Gemm(const Context& context, ScratchAllocator scratch)
    : context_(context), scratch_(std::move(scratch)) {
  tuning_ = apply_clblast_tuning(context_);
}

void Gemm::run(bool trans_a, bool trans_b, size_t m, size_t n, size_t k, float alpha, cl_mem a,
               size_t a_offset, size_t lda, cl_mem b, size_t b_offset, size_t ldb, float beta,
               cl_mem c, size_t c_offset, size_t ldc) {
  if (m == 0 || n == 0) return;
  const auto ta = trans_a ? clblast::Transpose::kYes : clblast::Transpose::kNo;
  const auto tb = trans_b ? clblast::Transpose::kYes : clblast::Transpose::kNo;
  cl_command_queue queue = context_.queue();
  size_t temp_bytes = 0;
  clblast::StatusCode status = clblast::GemmTempBufferSize<float>(
      clblast::Layout::kRowMajor, ta, tb, m, n, k, a_offset, lda, b_offset, ldb, c_offset, ldc,
      &queue, temp_bytes);
  check(status == clblast::StatusCode::kSuccess, "CLBlast GEMM ", m, "x", n, "x", k,
        ": querying its scratch size failed: ", status_text(status));
  ScratchBuffer temp;
  if (temp_bytes > 0) temp = scratch_(temp_bytes);
  status = clblast::Gemm<float>(clblast::Layout::kRowMajor, ta, tb, m, n, k, alpha, a, a_offset,
                                lda, b, b_offset, ldb, beta, c, c_offset, ldc, &queue, nullptr,
                                temp.mem);
  check(status == clblast::StatusCode::kSuccess, "CLBlast GEMM ", m, "x", n, "x", k,
        " failed: ", status_text(status));
}

}  // namespace facetool::opencl
