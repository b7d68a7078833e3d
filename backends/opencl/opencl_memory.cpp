// Device memory of the opencl backend: cl_mem buffers through the CachingAllocator, transfers.
#include <climits>

#include "backends/opencl/opencl_backend.h"
#include "core/util/error.h"

namespace facetool::opencl {
namespace {

class OpenclBuffer : public Buffer {
 public:
  OpenclBuffer(OpenclBackend& backend, cl_mem mem, size_t floats, size_t rounded_bytes)
      : backend_(backend), mem_(mem), floats_(floats), rounded_bytes_(rounded_bytes) {}
  ~OpenclBuffer() override { backend_.allocator().release(mem_, rounded_bytes_); }
  Backend& backend() const override { return backend_; }
  size_t size_floats() const override { return floats_; }
  cl_mem mem() const { return mem_; }

 private:
  OpenclBackend& backend_;
  cl_mem mem_;
  size_t floats_;
  size_t rounded_bytes_;
};

}  // namespace

cl_mem device_memory(const Tensor& t) {
  auto* buffer = dynamic_cast<OpenclBuffer*>(&t.buffer());
  check(buffer != nullptr, "tensor ", t.shape().str(), " lives on backend '", t.backend().name(),
        "', not on opencl; move it with Tensor::to()");
  return buffer->mem();
}

std::shared_ptr<Buffer> OpenclBackend::allocate(size_t floats) {
  // Kernels index with 32-bit ints.
  check(floats < static_cast<size_t>(INT_MAX), "opencl: a tensor of ", floats,
        " floats is larger than the backend supports (2^31 - 1 elements)");
  size_t rounded = 0;
  void* block = allocator_->acquire(std::max<size_t>(floats, 1) * sizeof(float), &rounded);
  return std::make_shared<OpenclBuffer>(*this, static_cast<cl_mem>(block), floats, rounded);
}

Tensor OpenclBackend::scratch(int64_t floats) {
  return Tensor::empty(*this, Shape{std::max<int64_t>(floats, 1)});
}

void OpenclBackend::upload(const Tensor& dst, const float* src) {
  check_cl(clEnqueueWriteBuffer(context_->queue(), device_memory(dst), CL_TRUE, 0,
                                static_cast<size_t>(dst.numel()) * sizeof(float), src, 0, nullptr,
                                nullptr),
           "clEnqueueWriteBuffer (upload)");
}

void OpenclBackend::download(const Tensor& src, float* dst) {
  check_cl(clEnqueueReadBuffer(context_->queue(), device_memory(src), CL_TRUE, 0,
                               static_cast<size_t>(src.numel()) * sizeof(float), dst, 0, nullptr,
                               nullptr),
           "clEnqueueReadBuffer (download)");
}

void OpenclBackend::synchronize() { context_->finish(); }

}  // namespace facetool::opencl
