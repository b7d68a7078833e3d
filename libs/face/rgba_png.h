// Writing pasted-back results with transparency: 8-bit RGBA PNGs.
#pragma once

#include <string>
#include <vector>

#include "libs/io/image_io.h"

namespace facetool {

// `rgb` (linear, sRGB-encoded on the way unless `encode_srgb` is false) with `alpha` (one
// value in [0, 1] per pixel) as an RGBA PNG, written atomically.
void write_rgba_png_atomically(const std::string& path, const RgbImage& rgb,
                               const std::vector<float>& alpha, bool encode_srgb = true);
// The bytes write_rgba_png_atomically writes (`path` names the file in errors).
std::vector<unsigned char> encode_rgba_png(const std::string& path, const RgbImage& rgb,
                                           const std::vector<float>& alpha, bool encode_srgb = true);

}  // namespace facetool
