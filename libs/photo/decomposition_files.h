// Files `facetool infer` writes per face crop, and the contact sheet that shows them side by side.
#pragma once

#include <string>
#include <vector>

#include "libs/inference/decomposer.h"
#include "libs/io/image_io.h"

namespace facetool {

// Writes image `index` of `d` into `folder` (created if needed):
//   input.png            the crop the network saw
//   reconstruction.png   re-rendered image (albedo * shading)
//   albedo.png/.exr      albedo (PNG sRGB-encoded; EXR linear)
//   shading.png/.exr     shading
//   normal.png/.exr      normals (PNG (n + 1) / 2 per channel; EXR the components)
//   visibility.png/.exr  ambient visibility v_0 / (2 sqrt(pi)) as grey; EXR all 9 coefficients
//   light.json           the 27 light coefficients (facetool format)
//   light.png            the light's preview: a lit sphere and the radiance panorama
// Every file is written under a temporary name and renamed.
void write_decomposition(const std::string& folder, const Decomposition& d, int index,
                         const std::vector<float>& input_planar, const std::string& source);

// One contact-sheet row for image `index`: input, reconstruction, albedo, shading, normal,
// visibility, each S x S, left to right.
RgbImage contact_sheet_row(const Decomposition& d, int index, const std::vector<float>& input_planar);
// Stacks rows (all the same width) with a 2-pixel gap; values are linear, the normal tile
// already display-encoded (the sheet is written sRGB-encoded, so it is decoded first).
RgbImage stack_rows(const std::vector<RgbImage>& rows);

}  // namespace facetool
