// CLBlast GEMM calls, the scratch buffer CLBlast needs, and the per-device tuning table.
#include "backends/opencl/clblast_gemm.h"

#include <clblast.h>

#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

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

// FACETOOL_CLBLAST_XGEMM="KWG=32,VWN=8": Xgemm parameters laid over the table (for tuning on
// a new device). A malformed entry is an error naming it.
Parameters xgemm_environment_overrides() {
  Parameters parameters;
  const char* env = std::getenv("FACETOOL_CLBLAST_XGEMM");
  if (!env) return parameters;
  std::string text = env;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    const std::string entry = text.substr(start, end - start);
    const size_t equals = entry.find('=');
    char* parsed_end = nullptr;
    const unsigned long value =
        equals == std::string::npos ? 0 : std::strtoul(entry.c_str() + equals + 1, &parsed_end, 10);
    check(equals != std::string::npos && equals > 0 && parsed_end && *parsed_end == '\0' &&
              equals + 1 < entry.size(),
          "FACETOOL_CLBLAST_XGEMM: '", entry, "' is not NAME=NUMBER (e.g. KWG=32,VWN=8)");
    parameters[entry.substr(0, equals)] = value;
    start = end + 1;
  }
  return parameters;
}

std::string status_text(clblast::StatusCode code) {
  return "CLBlast status " + std::to_string(static_cast<int>(code));
}

// Lays `overrides` over CLBlast's current parameters of `kernel` for this device (parameters
// not named, e.g. KREG, keep their values).
void override_kernel(const Context& context, const char* kernel, const Parameters& overrides) {
  Parameters parameters;
  clblast::RetrieveParameters(context.device(), kernel, clblast::Precision::kSingle, parameters);
  for (const auto& [key, value] : overrides) parameters[key] = value;
  const clblast::StatusCode status = clblast::OverrideParameters(
      context.device(), kernel, clblast::Precision::kSingle, parameters);
  check(status == clblast::StatusCode::kSuccess, "CLBlast: overriding the ", kernel,
        " parameters failed: ", status_text(status));
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
    for (const KernelOverride& entry : cpu_overrides())
      override_kernel(context, entry.kernel, entry.parameters);
    description = "CLBlast with the CPU tuning table";
  }
  const Parameters from_environment = xgemm_environment_overrides();
  if (!from_environment.empty()) {
    override_kernel(context, "Xgemm", from_environment);
    description += " + FACETOOL_CLBLAST_XGEMM";
  }
  applied.emplace(context.device(), description);
  return description;
}

Gemm::Gemm(const Context& context, ScratchAllocator scratch)
    : context_(context), scratch_(std::move(scratch)) {
  tuning_ = apply_clblast_tuning(context_);
  // CLBlast does not validate parameter sets: a hand-given one (e.g. NWG/NDIMC not a multiple
  // of VWN) can compute garbage silently. Check it once per device before any real work.
  static std::mutex mutex;
  static std::set<cl_device_id> checked;
  std::lock_guard<std::mutex> lock(mutex);
  if (!xgemm_environment_overrides().empty() && checked.insert(context_.device()).second)
    self_check();
}

void Gemm::self_check() {
  // Sizes off every tile multiple and large enough for CLBlast's indirect (tuned) kernel.
  const size_t m = 520, n = 264, k = 200;
  std::vector<float> a(m * k), b(k * n), c(m * n, 0.0f);
  for (size_t i = 0; i < a.size(); ++i) a[i] = static_cast<float>((i * 7 + 3) % 13) - 6.0f;
  for (size_t i = 0; i < b.size(); ++i) b[i] = static_cast<float>((i * 5 + 1) % 11) - 5.0f;
  const auto make = [&](std::vector<float>& host) {
    cl_int error = CL_SUCCESS;
    cl_mem mem = clCreateBuffer(context_.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                host.size() * sizeof(float), host.data(), &error);
    check(error == CL_SUCCESS, "CLBlast self-check: clCreateBuffer failed (", error, ")");
    return std::shared_ptr<_cl_mem>(mem, [](cl_mem m) { clReleaseMemObject(m); });
  };
  auto da = make(a), db = make(b), dc = make(c);
  for (bool trans_b : {false, true}) {
    // With trans_b the same b buffer is read as B^T stored [n, k].
    run(false, trans_b, m, n, k, 1.0f, da.get(), 0, k, db.get(), 0, trans_b ? k : n, 0.0f,
        dc.get(), 0, n);
    check(clEnqueueReadBuffer(context_.queue(), dc.get(), CL_TRUE, 0, c.size() * sizeof(float),
                              c.data(), 0, nullptr, nullptr) == CL_SUCCESS,
          "CLBlast self-check: reading the result failed");
    for (size_t i = 0; i < m; ++i)
      for (size_t j = 0; j < n; ++j) {
        double expected = 0.0;  // small integers: exact in float
        for (size_t p = 0; p < k; ++p)
          expected += a[i * k + p] * (trans_b ? b[j * k + p] : b[p * n + j]);
        check(c[i * n + j] == static_cast<float>(expected), "CLBlast with FACETOOL_CLBLAST_XGEMM='",
              std::getenv("FACETOOL_CLBLAST_XGEMM"), "' computes wrong results (C[", i, ", ", j,
              "] = ", c[i * n + j], ", expected ", expected,
              "): an invalid parameter combination (e.g. MWG/MDIMC not a multiple of VWM, or "
              "NWG/NDIMC not a multiple of VWN); fix or unset it");
      }
  }
}

void Gemm::run(bool trans_a, bool trans_b, size_t m, size_t n, size_t k, float alpha, cl_mem a,
               size_t a_offset, size_t lda, cl_mem b, size_t b_offset, size_t ldb, float beta,
               cl_mem c, size_t c_offset, size_t ldc) {
  if (m == 0 || n == 0) return;
  const auto ta = trans_a ? clblast::Transpose::kYes : clblast::Transpose::kNo;
  const auto tb = trans_b ? clblast::Transpose::kYes : clblast::Transpose::kNo;
  cl_command_queue queue = context_.queue();
  size_t temp_bytes = 0;
  // The row-major product C = op(A) op(B) is passed on as the column-major C^T = op(B)^T op(A)^T
  // (same memory). CLBlast's Xgemm kernel (GEMMK=0, the CPU table) takes column-major C and
  // K-major operands, so this order spares the copy-transpose of C on every call and, for the
  // convolution's GEMMs, of the large column matrices (~20% of PoCL time in row-major order).
  clblast::StatusCode status = clblast::GemmTempBufferSize<float>(
      clblast::Layout::kColMajor, tb, ta, n, m, k, b_offset, ldb, a_offset, lda, c_offset, ldc,
      &queue, temp_bytes);
  check(status == clblast::StatusCode::kSuccess, "CLBlast GEMM ", m, "x", n, "x", k,
        ": querying its scratch size failed: ", status_text(status));
  ScratchBuffer temp;
  if (temp_bytes > 0) temp = scratch_(temp_bytes);
  status = clblast::Gemm<float>(clblast::Layout::kColMajor, tb, ta, n, m, k, alpha, b, b_offset,
                                ldb, a, a_offset, lda, beta, c, c_offset, ldc, &queue, nullptr,
                                temp.mem);
  check(status == clblast::StatusCode::kSuccess, "CLBlast GEMM ", m, "x", n, "x", k,
        " failed: ", status_text(status));
}

}  // namespace facetool::opencl
