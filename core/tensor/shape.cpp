// Shape: construction, element counts and printing.
#include "core/tensor/shape.h"

#include "core/util/error.h"

namespace facetool {

Shape::Shape(std::initializer_list<int64_t> dims) {
  check(dims.size() <= static_cast<size_t>(kMaxRank), "Shape: rank ", dims.size(),
        " exceeds the maximum of ", kMaxRank);
  for (int64_t d : dims) {
    check(d >= 0, "Shape: negative dimension ", d);
    dims_[rank_++] = d;
  }
}

int64_t Shape::dim(int i) const {
  if (i < 0) i += rank_;
  // fail() directly: check() would build str() on every call, even when the index is valid.
  if (i < 0 || i >= rank_) fail("Shape ", str(), ": no dimension ", i);
  return dims_[i];
}

int64_t Shape::numel() const {
  int64_t count = 1;
  for (int i = 0; i < rank_; ++i) count *= dims_[i];
  return count;
}

static void require_nchw(const Shape& s) {
  if (s.rank() != 4) fail("expected an NCHW tensor of rank 4, got shape ", s.str());
}

int64_t Shape::n() const { require_nchw(*this); return dims_[0]; }
int64_t Shape::c() const { require_nchw(*this); return dims_[1]; }
int64_t Shape::h() const { require_nchw(*this); return dims_[2]; }
int64_t Shape::w() const { require_nchw(*this); return dims_[3]; }

std::string Shape::str() const {
  std::string out = "[";
  for (int i = 0; i < rank_; ++i) {
    if (i) out += ", ";
    out += std::to_string(dims_[i]);
  }
  return out + "]";
}

bool Shape::operator==(const Shape& other) const {
  if (rank_ != other.rank_) return false;
  for (int i = 0; i < rank_; ++i)
    if (dims_[i] != other.dims_[i]) return false;
  return true;
}

}  // namespace facetool
