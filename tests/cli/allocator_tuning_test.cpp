// keep_freed_memory_for_reuse (the program's start, apps/facetool/allocator_tuning.h): with
// glibc, an 8 MiB block comes from the heap instead of its own mapping, and once freed it stays
// in the heap for the next one (the default thresholds map it and hand it back at once).
#include <gtest/gtest.h>

#include <cstdlib>

#include "apps/facetool/allocator_tuning.h"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#include <malloc.h>
#endif

namespace facetool {
namespace {

TEST(AllocatorTuning, FreedBlocksBelow64MiBStayInTheHeap) {
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
  keep_freed_memory_for_reuse();
  const size_t size = 8u << 20;
  const struct mallinfo2 before = mallinfo2();
  void* block = std::malloc(size);
  ASSERT_NE(block, nullptr);
  static_cast<volatile char*>(block)[size - 1] = 1;
  const struct mallinfo2 held = mallinfo2();
  EXPECT_EQ(held.hblks, before.hblks) << "the block got its own mapping: the mmap threshold was not raised";
  std::free(block);
  const struct mallinfo2 after = mallinfo2();
  EXPECT_GE(after.fordblks, size) << "the freed block went back to the system: the trim threshold was not raised";
#else
  GTEST_SKIP() << "glibc's allocator only (not under AddressSanitizer, whose allocator replaces it)";
#endif
}

}  // namespace
}  // namespace facetool
