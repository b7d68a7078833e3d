// Spherical Fibonacci lattice: equal-area z bands with azimuths advancing by the golden angle.
#include "core/sh/sphere_samples.h"

#include <cmath>

#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool::sh {

std::vector<Vec3> fibonacci_sphere(int count) {
  check(count > 0, "fibonacci_sphere: the number of directions must be positive, got ", count);
  const double pi = kPi;
  const double golden_angle = pi * (3.0 - std::sqrt(5.0));
  std::vector<Vec3> dirs(static_cast<size_t>(count));
  for (int s = 0; s < count; ++s) {
    const double z = 1.0 - (2.0 * s + 1.0) / count;
    const double r = std::sqrt(std::fmax(0.0, 1.0 - z * z));
    const double phi = golden_angle * s;
    dirs[static_cast<size_t>(s)] = {r * std::cos(phi), r * std::sin(phi), z};
  }
  return dirs;
}

}  // namespace facetool::sh
