// Equirectangular environment maps projected to 27 SH coefficients (files: libs/light).
#pragma once

#include <string>
#include <vector>

#include "core/sh/sh_types.h"

namespace facetool::sh {

// A latitude-longitude panorama: width x height RGB pixels, row 0 at the top, stored
// row-major as r, g, b per pixel (linear radiance).
struct EnvironmentMap {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;
};

// Panorama coordinates to world directions. World frame: right-handed, +Y up, the camera at +Z
// looking down -Z (so +X is the viewer's right). u in [0, 1] runs left to right across the
// columns, v in [0, 1] top to bottom across the rows:
//   theta = pi v            (angle from +Y: the top row is straight up, the bottom straight down)
//   phi   = 2 pi (u - 1/2)  (azimuth about +Y, from -Z towards +X)
//   d     = (sin theta sin phi, cos theta, -sin theta cos phi)
// The centre of the panorama (u = v = 1/2) is -Z, the direction the camera looks (what lies
// behind the face); u = 3/4 is +X, u = 1/4 is -X, the left/right edges are +Z (behind the camera).
// A pixel (column c, row r) covers u in [c, c+1] / width and v in [r, r+1] / height.
Vec3 equirect_direction(double u, double v);

// f_i = integral L(w) Y_i(w) dw for the map taken as constant over each pixel. The integral over
// each pixel uses the exact solid-angle measure dw = sin(theta) dtheta dphi = d(cos theta) dphi
// with a 2 x 2 Gauss-Legendre rule in (cos theta, phi) inside the pixel; a constant map thus
// gives L_0 = 2 sqrt(pi) (and zero elsewhere) to rounding. Output channel-major R0..R8 G0..B8.
RgbLight project_environment_map(const EnvironmentMap& map);

}  // namespace facetool::sh
