// A size-bucketed cache of device or host allocations, so hot loops never hit the system allocator.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <mutex>

namespace facetool {

// Hands out blocks of at least the requested size; released blocks are kept and reused for
// later requests of the same rounded size instead of being returned to the system. Sizes are
// rounded up to a multiple of 1/8 of their power of two, so a reused block wastes at most 12.5%.
// The raw allocate/free functions are the backend's (malloc, clCreateBuffer, ...).
class CachingAllocator {
 public:
  using AllocateFn = std::function<void*(size_t bytes)>;
  using FreeFn = std::function<void(void* block, size_t bytes)>;

  CachingAllocator(AllocateFn allocate, FreeFn free);
  ~CachingAllocator();
  CachingAllocator(const CachingAllocator&) = delete;
  CachingAllocator& operator=(const CachingAllocator&) = delete;

  // Returns a block of rounded_size(bytes) bytes, reusing a cached one when possible.
  void* acquire(size_t bytes, size_t* rounded_bytes);
  // Gives a block obtained from acquire back to the cache.
  void release(void* block, size_t rounded_bytes);
  // Frees every cached block (blocks in use are untouched).
  void trim();

  static size_t rounded_size(size_t bytes);
  size_t cached_bytes() const;
  size_t live_bytes() const;

 private:
  AllocateFn allocate_;
  FreeFn free_;
  mutable std::mutex mutex_;
  std::multimap<size_t, void*> free_blocks_;
  size_t cached_bytes_ = 0;
  size_t live_bytes_ = 0;
};

}  // namespace facetool
