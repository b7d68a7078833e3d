// A picture of an SH light for people: a lit sphere and the radiance panorama, side by side.
#pragma once

#include <string>

#include "libs/io/image_io.h"
#include "core/sh/sh_types.h"

namespace facetool::light {

// The picture is 3 * size wide and size high:
// - left square: the hemisphere facing the camera (orthographic view down -Z, +Y up, +X right),
//   albedo 1, unoccluded, i.e. what facetool's renderer gives: shading(n) = 1/pi * sum_i A_l
//   L_i Y_i(n) with A_l = pi, 2pi/3, pi/4; on a background of dark grey;
// - right 2:1 panel: the radiance L(w) as an equirectangular panorama with the mapping of
//   sh::equirect_direction (top row up, centre -Z = straight ahead of the camera, u = 3/4 is
//   +X, the left/right edges +Z = behind the camera), with thin grey guide lines at the horizon
//   and at u = 1/4, 1/2, 3/4.
// Each panel is divided by its own largest channel value (linear), then sRGB-encoded by the PNG
// writer. Where any channel is negative (SH lights can dip below zero) the pixel shows its
// positive part crossed by blue diagonal hatching.
struct LightPreview {
  RgbImage image;
  double shading_max = 0;   // largest shading channel value on the sphere
  double radiance_max = 0;  // largest radiance channel value in the panorama
  double radiance_min = 0;  // smallest radiance channel value (< 0: the light dips below zero)
  bool negative_shading = false;
};

// `size` is the panel height in pixels (16..4096, else facetool::Error).
LightPreview render_light_preview(const sh::RgbLight& light, int size = 256);

// render_light_preview written atomically as an 8-bit PNG at `path`.
LightPreview write_light_preview(const std::string& path, const sh::RgbLight& light,
                                 int size = 256);

}  // namespace facetool::light
