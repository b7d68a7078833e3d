// Shape of a tensor: up to four dimensions, read as NCHW when there are four.
#pragma once

#include <array>
#include <cstdint>
#include <initializer_list>
#include <string>

namespace facetool {

class Shape {
 public:
  static constexpr int kMaxRank = 4;

  Shape() = default;  // rank 0: a scalar holding one element
  Shape(std::initializer_list<int64_t> dims);

  int rank() const { return rank_; }
  int64_t dim(int i) const;   // negative i counts from the back
  int64_t operator[](int i) const { return dim(i); }
  int64_t numel() const;

  // NCHW accessors; valid only for rank-4 shapes (checked).
  int64_t n() const;
  int64_t c() const;
  int64_t h() const;
  int64_t w() const;

  std::string str() const;  // "[20, 128, 64, 64]"
  bool operator==(const Shape& other) const;
  bool operator!=(const Shape& other) const { return !(*this == other); }

 private:
  std::array<int64_t, kMaxRank> dims_{0, 0, 0, 0};
  int rank_ = 0;
};

}  // namespace facetool
