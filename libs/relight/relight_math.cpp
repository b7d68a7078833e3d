// Relighting arithmetic: the two modes, the guarded shading ratio, orbits and the open hemisphere.
#include "libs/relight/relight_math.h"

#include <algorithm>
#include <cmath>

#include "core/sh/sh_rotation.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool::relight {
namespace {
}

Mode mode_from_name(const std::string& name) {
  if (name == "render") return Mode::Render;
  if (name == "ratio") return Mode::Ratio;
  fail("relight mode must be 'ratio' (photo x new / old shading) or 'render' (albedo x new "
       "shading); got '", name, "'");
}

float ratio_factor(float new_shading, float old_shading, float epsilon) {
  return (std::max(new_shading, 0.0f) + epsilon) / (std::max(old_shading, 0.0f) + epsilon);
}

void apply_ratio(const float* photo, const float* old_shading, const float* new_shading,
                 size_t plane, float epsilon, float* out) {
  for (size_t i = 0; i < 3 * plane; ++i)
    out[i] = photo[i] * ratio_factor(new_shading[i], old_shading[i], epsilon);
}

sh::ShCoeffs open_visibility() {
  sh::ShCoeffs v{};
  v[0] = 2.0 * std::sqrt(kPi);
  return v;
}

sh::Mat3 rotation_about_vertical(double degrees) {
  const double a = degrees * kPi / 180.0, c = std::cos(a), s = std::sin(a);
  return sh::Mat3{{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}};
}

sh::RgbLight orbit_light(const sh::RgbLight& light, int frame, int frames) {
  check(frames >= 1, "an orbit needs at least one frame");
  return sh::rotate_light(light, rotation_about_vertical(360.0 * frame / frames));
}

sh::RgbLight scale_light(const sh::RgbLight& light, double intensity) {
  sh::RgbLight out = light;
  for (double& c : out) c *= intensity;
  return out;
}

}  // namespace facetool::relight
