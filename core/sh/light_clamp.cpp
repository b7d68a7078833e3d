// Re-projection of max(0, L(w)) for lights that are negative somewhere on the sphere.
#include "core/sh/light_clamp.h"

#include <algorithm>
#include <limits>
#include <vector>

#include "core/sh/sh_eval.h"
#include "core/sh/sh_projection.h"
#include "core/sh/sphere_samples.h"

namespace facetool::sh {

double min_radiance(const ShCoeffs& channel, int sample_count) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const Vec3& d : fibonacci_sphere(sample_count))
    lowest = std::min(lowest, sh_eval(channel, d));
  return lowest;
}

ShCoeffs clamp_nonnegative(const ShCoeffs& channel, int sample_count) {
  const std::vector<Vec3> dirs = fibonacci_sphere(sample_count);
  std::vector<double> values(dirs.size());
  bool negative = false;
  for (size_t s = 0; s < dirs.size(); ++s) {
    values[s] = sh_eval(channel, dirs[s]);
    if (values[s] < 0.0) {
      negative = true;
      values[s] = 0.0;
    }
  }
  return negative ? project_samples(dirs, values) : channel;
}

RgbLight clamp_light_nonnegative(const RgbLight& light, int sample_count) {
  RgbLight out{};
  for (int c = 0; c < 3; ++c)
    set_light_channel(out, c, clamp_nonnegative(light_channel(light, c), sample_count));
  return out;
}

}  // namespace facetool::sh
