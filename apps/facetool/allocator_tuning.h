// The C library allocator's thresholds for a process that allocates and frees photo-sized buffers.
#pragma once

namespace facetool {

// With glibc, keeps freed blocks below 64 MiB in the heap for reuse (mmap threshold 64 MiB, trim
// threshold 256 MiB) instead of returning each to the system and faulting its pages in again on
// the next photo (docs/performance.md, "Whole photos"). Larger blocks (a 12 MP photo's planes)
// still come from and go back to the system. Elsewhere a no-op. Call once, before threads start.
void keep_freed_memory_for_reuse();

}  // namespace facetool
