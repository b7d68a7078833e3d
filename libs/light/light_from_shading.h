// The light from a face's shading: a distant white light plus ambient, then its colour, fitted robustly through the renderer.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "core/sh/sh_types.h"

namespace facetool {

// One face crop's buffers, planar, S x S = `plane` pixels: `image` [3] linear RGB, `albedo` [3]
// (the network's), `normal` [3] unit vectors, `visibility` [9] SH coefficients, `mask` [1] the
// face's weight (pixels above 0.5 are fitted).
struct ShadingInputs {
  const float* image = nullptr;
  const float* albedo = nullptr;
  const float* normal = nullptr;
  const float* visibility = nullptr;
  const float* mask = nullptr;
  int size = 0;
};

// The light found, in the crop's frame (+X right, +Y up, +Z to the viewer, docs/conventions.md).
struct DistantLight {
  sh::Vec3 direction{0.0, 0.0, 1.0};       // unit, towards the light
  std::array<double, 3> ambient{};         // radiance of the uniform part, per colour
  std::array<double, 3> intensity{};       // the distant light's power per colour (irradiance at normal incidence)
  double relative_residual = 0;            // robust RMS residual / mean intensity over the fitted pixels
  size_t pixels = 0;                       // pixels fitted (after the outlier weights: weight above one half)
  bool solved = false;                     // false: too few usable pixels; the light is the caller's
  std::string warning;                     // empty, or why the light should not be trusted
};

// Fewer face pixels than this, or fewer than a quarter of it usable (lit, unsaturated; every
// second pixel of every second row is fitted), leave the light unsolved, with a warning.
constexpr size_t kMinLightSolvePixels = 200;

// The 27 SH radiance coefficients (channel-major, the renderer's convention) of `light`: per colour
// c, L_c(w) = ambient_c + intensity_c delta(w, direction), projected on the 9 functions:
// L_c0 = sqrt(4 pi) ambient_c + intensity_c Y_0(d), L_ci = intensity_c Y_i(d) for i > 0.
sh::RgbLight sh_light(const DistantLight& light);

// The distant white light plus ambient, times a gain per colour, that makes the renderer (I_c = albedo_c / pi *
// sum_i L_ci transfer_i, core/sh/pixel_transfer.h) explain the face's pixels best:
//   - the albedo in the fit is the network's fine detail (its albedo over its own blur of radius
//     S / 32, dark features left out of the blur) times its mean over the face: brows, lashes and
//     lips stay dark, while the shading the network left in its albedo (smooth over the face) is
//     the light's to explain;
//   - for each of the 2,000 directions of a Fibonacci sphere within 120 degrees of the camera axis
//     (then 1,000 within 6 degrees of the best), ambient and intensity >= 0 by linear least
//     squares through 9 x 9 moments of the pixels: a direction costs 81 multiply-adds, not a pass
//     over the pixels;
//   - every second pixel of every second row (a quarter of the face is plenty for 5 numbers);
//   - robust: saturated pixels (a channel above 0.95) and black ones are left out, then four rounds
//     of Cauchy weights on the residuals (specular highlights, hair, glasses, cast shadows the
//     visibility misses), the direction searched again each round;
//   - then, at the direction found, ambient and intensity again with the ambient no brighter than
//     what the distant light leaves of the darkest 15 % of the face's pixels: on a face's normals
//     an ambient and a light near the camera shade nearly alike, and the free fit takes too much
//     ambient (docs/photos.md, "The light from the shading");
//   - one white light is fitted to the three colours together, then each colour of it scaled by
//     its least-squares gain over the weighted pixels (a light whose ambient and distant parts
//     differ in colour from one colour to the next tints the shadows); a grey crop (its three
//     channels equal at every fitted pixel) keeps the white light: a grey photo says nothing of
//     the light's colour.
// A light behind the plane facing the camera (over 90 degrees from its axis), a face mostly in
// shadow (its median brightness under 8 % of its 99th percentile), or a fit that leaves more than
// half the mean brightness unexplained is returned with a warning (the light is still finite).
DistantLight solve_distant_light(const ShadingInputs& in);

}  // namespace facetool
