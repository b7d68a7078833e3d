// Host memory of the cpu backend: 64-byte aligned blocks handed out by a CachingAllocator.
#include <cstdlib>
#include <cstring>

#include "backends/cpu/cpu_backend_impl.h"
#include "core/util/error.h"

namespace facetool::cpu {
namespace {

constexpr size_t kAlignment = 64;

void* aligned_block(size_t bytes) {
  const size_t rounded = (bytes + kAlignment - 1) / kAlignment * kAlignment;
  return std::aligned_alloc(kAlignment, rounded);
}

// A host buffer that goes back to the allocator's cache when the last tensor releases it. It
// keeps the allocator alive so buffers may outlive the backend object.
class CpuBuffer final : public Buffer {
 public:
  CpuBuffer(Backend& backend, std::shared_ptr<CachingAllocator> allocator, size_t floats)
      : backend_(backend), allocator_(std::move(allocator)), floats_(floats) {
    data_ = static_cast<float*>(allocator_->acquire(floats * sizeof(float), &bytes_));
  }
  ~CpuBuffer() override { allocator_->release(data_, bytes_); }

  Backend& backend() const override { return backend_; }
  size_t size_floats() const override { return floats_; }
  float* host_data() const override { return data_; }

 private:
  Backend& backend_;
  std::shared_ptr<CachingAllocator> allocator_;
  size_t floats_;
  float* data_ = nullptr;
  size_t bytes_ = 0;
};

}  // namespace

CpuBackend::CpuBackend()
    : allocator_(std::make_shared<CachingAllocator>(
          aligned_block, [](void* block, size_t) { std::free(block); })) {}

std::shared_ptr<Buffer> CpuBackend::allocate(size_t floats) {
  return std::make_shared<CpuBuffer>(*this, allocator_, floats);
}

void CpuBackend::upload(const Tensor& dst, const float* src) {
  std::memcpy(ptr(dst), src, static_cast<size_t>(dst.numel()) * sizeof(float));
}

void CpuBackend::download(const Tensor& src, float* dst) {
  std::memcpy(dst, ptr(src), static_cast<size_t>(src.numel()) * sizeof(float));
}

CpuBackend::Scratch::Scratch(CachingAllocator& allocator, size_t floats)
    : allocator_(allocator) {
  data_ = static_cast<float*>(allocator_.acquire(floats * sizeof(float), &bytes_));
}

CpuBackend::Scratch::~Scratch() { allocator_.release(data_, bytes_); }

}  // namespace facetool::cpu
