// Per-thread scratch memory that persists across calls, so hot loops never allocate.
#pragma once

#include <cstddef>

namespace facetool::cpu {

// A block of at least `floats` floats owned by the calling thread; valid until the same thread
// asks again. Grows when needed and is then reused by every later call on that thread.
float* thread_workspace(size_t floats);

}  // namespace facetool::cpu
