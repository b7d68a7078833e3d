// thread_workspace: one growing 64-byte aligned block per thread.
#include "backends/cpu/cpu_workspace.h"

#include <cstdlib>
#include <memory>

#include "core/util/error.h"
#include "core/util/memory_budget.h"

namespace facetool::cpu {
namespace {

struct FreeDeleter {
  void operator()(float* p) const { std::free(p); }
};

}  // namespace

float* thread_workspace(size_t floats) {
  thread_local std::unique_ptr<float, FreeDeleter> block;
  thread_local size_t capacity = 0;
  if (floats > capacity) {
    const size_t bytes = (floats * sizeof(float) + 63) / 64 * 64;
    block.reset(static_cast<float*>(std::aligned_alloc(64, bytes)));
    if (block == nullptr) throw out_of_memory("allocating the cpu backend's workspace", bytes);
    capacity = bytes / sizeof(float);
  }
  return block.get();
}

}  // namespace facetool::cpu
