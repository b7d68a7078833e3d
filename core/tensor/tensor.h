// Tensor: a float32 array of up to four dimensions (NCHW) living in one backend's buffer.
#pragma once

#include <memory>
#include <vector>

#include "core/tensor/shape.h"

namespace facetool {

class Backend;

// A block of device memory owned by a backend. Freed (or returned to the backend's cache)
// when the last tensor that uses it goes away.
class Buffer {
 public:
  virtual ~Buffer() = default;
  virtual Backend& backend() const = 0;
  virtual size_t size_floats() const = 0;
  // Host-addressable memory, or nullptr when the buffer lives on a device.
  virtual float* host_data() const { return nullptr; }
};

class Tensor {
 public:
  Tensor() = default;  // undefined: holds no buffer

  // Allocates uninitialised storage on `backend`.
  static Tensor empty(Backend& backend, const Shape& shape);
  static Tensor zeros(Backend& backend, const Shape& shape);
  static Tensor full(Backend& backend, const Shape& shape, float value);
  // Copies `values` (exactly shape.numel() of them) to a new tensor on `backend`.
  static Tensor from_host(Backend& backend, const Shape& shape, const std::vector<float>& values);

  bool defined() const { return buffer_ != nullptr; }
  const Shape& shape() const { return shape_; }
  int64_t numel() const { return shape_.numel(); }
  Backend& backend() const;
  Buffer& buffer() const;
  // The host pointer of a host-resident tensor (cpu backend); fails for device tensors.
  float* host_data() const;

  std::vector<float> to_host() const;
  void copy_from_host(const std::vector<float>& values) const;
  // Same storage viewed with another shape of equal element count.
  Tensor reshaped(const Shape& shape) const;
  // A new tensor on `target` holding the same values.
  Tensor to(Backend& target) const;
  // A new tensor on the same backend holding a copy of the values.
  Tensor clone() const;

 private:
  Tensor(std::shared_ptr<Buffer> buffer, const Shape& shape);
  std::shared_ptr<Buffer> buffer_;
  Shape shape_;
};

}  // namespace facetool
