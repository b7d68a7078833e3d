// The tests' one finite-difference helper: the central difference of a scalar function in one of
// the values it reads.
#pragma once

#include <functional>

namespace facetool::testing {

// d f / d x at the value `x` (a float or double that f reads, changed in place and restored):
// (f(x + h) - f(x - h)) / ((x + h) - (x - h)), the denominator being the step as stored in T, so
// float rounding of x +- h does not bias the quotient. Values f derived from x (a device copy)
// are the caller's to refresh after the call.
template <typename T>
double central_difference(T& x, double h, const std::function<double()>& f) {
  const T keep = x;
  x = static_cast<T>(keep + h);
  const double up_at = static_cast<double>(x);
  const double up = f();
  x = static_cast<T>(keep - h);
  const double down_at = static_cast<double>(x);
  const double down = f();
  x = keep;
  return (up - down) / (up_at - down_at);
}

}  // namespace facetool::testing
