// A distant light plus ambient from angles in degrees, through the light solve's SH projection.
#include "libs/light/direction_light.h"

#include <cmath>

#include "core/util/error.h"
#include "core/util/math_constants.h"
#include "libs/light/light_from_shading.h"

namespace facetool::light {

sh::Vec3 direction_from_angles(double azimuth_deg, double elevation_deg) {
  check(std::isfinite(azimuth_deg) && std::isfinite(elevation_deg) && std::abs(azimuth_deg) <= 360 &&
            std::abs(elevation_deg) <= 360,
        "light direction: azimuth and elevation must be finite angles in degrees within -360..360, got ",
        azimuth_deg, ", ", elevation_deg);
  const double a = azimuth_deg * kPi / 180.0, e = elevation_deg * kPi / 180.0;
  return {std::sin(a) * std::cos(e), std::sin(e), std::cos(a) * std::cos(e)};
}

sh::RgbLight light_from_direction(double azimuth_deg, double elevation_deg, double ambient, double intensity) {
  check(std::isfinite(ambient) && ambient >= 0 && ambient <= 1e6, "light direction: the ambient must be within 0..1e6, got ",
        ambient);
  check(std::isfinite(intensity) && intensity >= 0 && intensity <= 1e6,
        "light direction: the intensity must be within 0..1e6, got ", intensity);
  DistantLight light;
  light.direction = direction_from_angles(azimuth_deg, elevation_deg);
  // The renderer's shading is 1/pi of the irradiance: a delta of power pi I shades I max(0, n.l).
  light.ambient = {ambient, ambient, ambient};
  light.intensity = {kPi * intensity, kPi * intensity, kPi * intensity};
  return sh_light(light);
}

}  // namespace facetool::light
