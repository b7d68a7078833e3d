// Light rotations given on the command line: "yaw,pitch,roll" in degrees (light from-envmap, relight).
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

std::array<double, 3> parse_rotation(const std::string& text) {
  std::array<double, 3> angles{};
  std::istringstream in(text);
  std::string part;
  int count = 0;
  bool ok = true;
  while (std::getline(in, part, ',')) {
    char* end = nullptr;
    const double value = std::strtod(part.c_str(), &end);
    if (count >= 3 || part.empty() || *end != '\0' || !std::isfinite(value)) ok = false;
    if (count < 3) angles[count] = value;
    ++count;
  }
  if (!ok || count != 3)
    throw UsageError("--rotate expects yaw,pitch,roll in degrees such as 30,0,0 (write "
                     "--rotate=-30,0,0 for a negative first angle); got '" + text + "'");
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
