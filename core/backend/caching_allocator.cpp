// CachingAllocator: bucketed reuse of released blocks.
#include "core/backend/caching_allocator.h"

#include "core/util/error.h"
#include "core/util/memory_budget.h"

namespace facetool {

CachingAllocator::CachingAllocator(AllocateFn allocate, FreeFn free)
    : allocate_(std::move(allocate)), free_(std::move(free)) {}

CachingAllocator::~CachingAllocator() { trim(); }

size_t CachingAllocator::rounded_size(size_t bytes) {
  if (bytes <= 256) return 256;
  size_t power = 1;
  while (power < bytes) power <<= 1;
  const size_t step = power / 8;
  return (bytes + step - 1) / step * step;
}

void* CachingAllocator::acquire(size_t bytes, size_t* rounded_bytes) {
  const size_t size = rounded_size(bytes);
  *rounded_bytes = size;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = free_blocks_.find(size);
    if (it != free_blocks_.end()) {
      void* block = it->second;
      free_blocks_.erase(it);
      cached_bytes_ -= size;
      live_bytes_ += size;
      return block;
    }
  }
  void* block = allocate_(size);
  if (block == nullptr) {
    // Out of memory: give the cache back and try once more.
    trim();
    block = allocate_(size);
  }
  // An OutOfMemory, so that the step that asked for the tensor can name itself
  // (naming_out_of_memory).
  if (block == nullptr) throw out_of_memory("allocating a tensor", size);
  std::lock_guard<std::mutex> lock(mutex_);
  live_bytes_ += size;
  return block;
}

void CachingAllocator::release(void* block, size_t rounded_bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  free_blocks_.emplace(rounded_bytes, block);
  cached_bytes_ += rounded_bytes;
  live_bytes_ -= rounded_bytes;
}

void CachingAllocator::trim() {
  std::multimap<size_t, void*> blocks;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    blocks.swap(free_blocks_);
    cached_bytes_ = 0;
  }
  for (auto& [size, block] : blocks) free_(block, size);
}

size_t CachingAllocator::cached_bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return cached_bytes_;
}

size_t CachingAllocator::live_bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return live_bytes_;
}

}  // namespace facetool
