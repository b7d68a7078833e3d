// Integrating equirectangular maps against the SH per pixel (files are read by libs/light).
#include "core/sh/envmap_projection.h"

#include <cmath>

#include "core/sh/sh_basis.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool::sh {
namespace {
}

Vec3 equirect_direction(double u, double v) {
  const double theta = kPi * v;
  const double phi = 2.0 * kPi * (u - 0.5);
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

RgbLight project_environment_map(const EnvironmentMap& map) {
  check(map.width > 0 && map.height > 0 &&
            map.rgb.size() == static_cast<size_t>(map.width) * map.height * 3,
        "environment map: ", map.width, "x", map.height, " with ", map.rgb.size(),
        " values; expected width * height * 3 RGB values");
  const double node = 0.5 / std::sqrt(3.0);  // 2-point Gauss-Legendre nodes at 1/2 -+ node
  const double dphi = 2.0 * kPi / map.width;
  // Per column: the azimuths of the two nodes. Per row: t = cos(theta) of the two nodes.
  std::vector<double> sin_phi(static_cast<size_t>(map.width) * 2),
      cos_phi(static_cast<size_t>(map.width) * 2);
  for (int c = 0; c < map.width; ++c)
    for (int q = 0; q < 2; ++q) {
      const double phi = 2.0 * kPi * ((c + 0.5 + (q ? node : -node)) / map.width - 0.5);
      sin_phi[c * 2 + q] = std::sin(phi);
      cos_phi[c * 2 + q] = std::cos(phi);
    }
  double sums[3][kCoeffCount] = {};
  for (int r = 0; r < map.height; ++r) {
    const double t_top = std::cos(kPi * r / map.height);
    const double t_bottom = std::cos(kPi * (r + 1) / map.height);
    const double dt = t_top - t_bottom;  // solid angle of the row per radian of azimuth
    double t_node[2], s_node[2];
    for (int q = 0; q < 2; ++q) {
      t_node[q] = 0.5 * (t_top + t_bottom) + (q ? node : -node) * dt;
      s_node[q] = std::sqrt(std::fmax(0.0, 1.0 - t_node[q] * t_node[q]));
    }
    const double weight = 0.25 * dt * dphi;  // each of the 4 nodes of a pixel
    for (int c = 0; c < map.width; ++c) {
      double basis_integral[kCoeffCount] = {};
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          double y[kCoeffCount];
          sh_basis(s_node[a] * sin_phi[c * 2 + b], t_node[a], -s_node[a] * cos_phi[c * 2 + b], y);
          for (int i = 0; i < kCoeffCount; ++i) basis_integral[i] += weight * y[i];
        }
      const float* px = &map.rgb[(static_cast<size_t>(r) * map.width + c) * 3];
      for (int ch = 0; ch < 3; ++ch)
        for (int i = 0; i < kCoeffCount; ++i) sums[ch][i] += px[ch] * basis_integral[i];
    }
  }
  RgbLight out{};
  for (int ch = 0; ch < 3; ++ch)
    for (int i = 0; i < kCoeffCount; ++i) out[ch * kCoeffCount + i] = sums[ch][i];
  return out;
}

}  // namespace facetool::sh
