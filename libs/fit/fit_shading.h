// Light and albedo from a photo given the fit's normals and visibility: the 27 SH light
// coefficients by linear least squares, then a smooth albedo by local least squares, twice
// (docs/fit.md, "Light and albedo").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/sh/pixel_transfer.h"
#include "core/sh/sh_types.h"

namespace facetool {

struct ShadingSolveSettings {
  int rounds = 2;              // light solve, albedo solve; repeated
  // Ridge on the light's orders 1-2, relative to the least-squares system's mean diagonal.
  double light_ridge = 1e-2;
  int albedo_radius = 0;       // box radius of the local albedo fit, pixels (0: width / 40, at least 1)
  // The ambiguity albedo_c x k_c, light_c / k_c is fixed by a light whose DC term is the same in
  // every channel and by this mean albedo over the mask and channels.
  double mean_albedo = 0.5;
};

struct ShadingSolve {
  sh::RgbLight light{};        // 27, channel-major, the renderer's convention
  std::vector<float> albedo;   // planar [3][width * height], in [0, 1], 0 outside the mask
  double rms_residual = 0;     // RMS of image - rendering over the mask, linear units
};

// `image` planar [3][w*h] linear RGB, `normal` [3], `visibility` [9], `mask` 1 where the fit is
// trusted. Throws facetool::Error when the mask has fewer than 27 pixels.
ShadingSolve solve_light_and_albedo(const std::vector<float>& image, const std::vector<float>& normal,
                                    const std::vector<float>& visibility, const std::vector<uint8_t>& mask,
                                    int width, int height, const ShadingSolveSettings& settings = {});

}  // namespace facetool
