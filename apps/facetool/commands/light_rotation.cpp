// Light angles given on the command line: rotations (light from-envmap, relight) and directions (light from-direction, relight).
#include "apps/facetool/commands/light_rotation.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "apps/facetool/commands/command.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {


sh::Mat3 multiply(const sh::Mat3& a, const sh::Mat3& b) {
  sh::Mat3 out{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) out[i][j] += a[i][k] * b[k][j];
  return out;
}

}  // namespace

namespace {

// Comma-separated finite numbers; false when `text` does not hold exactly `count` of them.
bool parse_angles(const std::string& text, double* angles, int count) {
  std::istringstream in(text);
  std::string part;
  int found = 0;
  bool ok = true;
  while (std::getline(in, part, ',')) {
    char* end = nullptr;
    const double value = std::strtod(part.c_str(), &end);
    if (found >= count || part.empty() || *end != '\0' || !std::isfinite(value)) ok = false;
    if (found < count) angles[found] = value;
    ++found;
  }
  return ok && found == count;
}

}  // namespace

std::array<double, 3> parse_rotation(const std::string& text) {
  std::array<double, 3> angles{};
  if (!parse_angles(text, angles.data(), 3))
    throw UsageError("--rotate expects yaw,pitch,roll in degrees such as 30,0,0 (write "
                     "--rotate=-30,0,0 for a negative first angle); got '" + text + "'");
  return angles;
}

std::array<double, 2> parse_azimuth_elevation(const std::string& text) {
  std::array<double, 2> angles{};
  if (!parse_angles(text, angles.data(), 2) || std::abs(angles[0]) > 360 || std::abs(angles[1]) > 90)
    throw UsageError("a light direction is azimuth,elevation in degrees such as 40,20 (azimuth within -360..360, "
                     "elevation within -90..90; write --light-direction=-40,20 for a negative azimuth); got '" +
                     text + "'");
  return angles;
}

sh::Mat3 rotation_from_yaw_pitch_roll(const std::array<double, 3>& degrees) {
  const double y = degrees[0] * kPi / 180, p = degrees[1] * kPi / 180, r = degrees[2] * kPi / 180;
  const sh::Mat3 ry{{{std::cos(y), 0, std::sin(y)}, {0, 1, 0}, {-std::sin(y), 0, std::cos(y)}}};
  const sh::Mat3 rx{{{1, 0, 0}, {0, std::cos(p), -std::sin(p)}, {0, std::sin(p), std::cos(p)}}};
  const sh::Mat3 rz{{{std::cos(r), -std::sin(r), 0}, {std::sin(r), std::cos(r), 0}, {0, 0, 1}}};
  return multiply(ry, multiply(rx, rz));
}

}  // namespace facetool
