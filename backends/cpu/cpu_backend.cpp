// The cpu backend's factory and its device description.
#include "backends/cpu/cpu_backend.h"

#include <fstream>
#include <string>

#include "backends/cpu/cpu_backend_impl.h"
#include "backends/cpu/gemm.h"
#include "core/util/parallel_for.h"

namespace facetool {
namespace cpu {
namespace {

std::string cpu_model_name() {
  std::ifstream info("/proc/cpuinfo");
  std::string line;
  while (std::getline(info, line)) {
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "host CPU";
}

}  // namespace

std::string CpuBackend::device_description() const {
  return cpu_model_name() + ", " + std::to_string(parallel_thread_count()) + " threads, " +
         sgemm_description();
}

}  // namespace cpu

std::unique_ptr<Backend> make_cpu_backend() { return std::make_unique<cpu::CpuBackend>(); }

}  // namespace facetool
