// glibc's mallopt thresholds for photo-sized buffers (see allocator_tuning.h).
#include "apps/facetool/allocator_tuning.h"

#include <cstdlib>  // defines __GLIBC__ with the GNU C library

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace facetool {

void keep_freed_memory_for_reuse() {
#if defined(__GLIBC__)
  // Setting either threshold turns off glibc's dynamic adjustment of both, so both are set.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace facetool
