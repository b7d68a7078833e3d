// Tensor: allocation through the owning backend, host transfers and reshaping.
#include "core/tensor/tensor.h"

#include "core/backend/backend.h"
#include "core/util/error.h"

namespace facetool {

Tensor::Tensor(std::shared_ptr<Buffer> buffer, const Shape& shape)
    : buffer_(std::move(buffer)), shape_(shape) {}

Tensor Tensor::empty(Backend& backend, const Shape& shape) {
  return Tensor(backend.allocate(static_cast<size_t>(shape.numel())), shape);
}

Tensor Tensor::zeros(Backend& backend, const Shape& shape) { return full(backend, shape, 0.0f); }

Tensor Tensor::full(Backend& backend, const Shape& shape, float value) {
  Tensor t = empty(backend, shape);
  if (t.numel() > 0) backend.fill(t, value);
  return t;
}

Tensor Tensor::from_host(Backend& backend, const Shape& shape, const std::vector<float>& values) {
  Tensor t = empty(backend, shape);
  t.copy_from_host(values);
  return t;
}

Backend& Tensor::backend() const { return buffer().backend(); }

Buffer& Tensor::buffer() const {
  check(buffer_ != nullptr, "use of an undefined tensor (it was never allocated)");
  return *buffer_;
}

float* Tensor::host_data() const {
  float* p = buffer().host_data();
  // fail() directly rather than check(): this runs in every cpu op, and check() would format
  // the shape even when the pointer is fine.
  if (p == nullptr)
    fail("tensor ", shape_.str(), " lives on backend '", backend().name(),
         "' and has no host pointer; download it with to_host()");
  return p;
}

std::vector<float> Tensor::to_host() const {
  std::vector<float> out(static_cast<size_t>(numel()));
  if (!out.empty()) backend().download(*this, out.data());
  return out;
}

void Tensor::copy_from_host(const std::vector<float>& values) const {
  check(static_cast<int64_t>(values.size()) == numel(), "copy_from_host: tensor ", shape_.str(),
        " holds ", numel(), " values but ", values.size(), " were given");
  if (!values.empty()) backend().upload(*this, values.data());
}

Tensor Tensor::reshaped(const Shape& shape) const {
  check(shape.numel() == numel(), "reshape: cannot view ", shape_.str(), " (", numel(),
        " values) as ", shape.str(), " (", shape.numel(), " values)");
  return Tensor(buffer_, shape);
}

Tensor Tensor::to(Backend& target) const {
  if (&target == &backend()) return clone();
  return from_host(target, shape_, to_host());
}

Tensor Tensor::clone() const {
  Tensor t = empty(backend(), shape_);
  if (numel() > 0) backend().copy(*this, t);
  return t;
}

}  // namespace facetool
