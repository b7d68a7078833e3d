// Reading the component images of `facetool render` (albedo, normal, visibility, mask) from files.
#pragma once

#include <string>
#include <vector>

#include "libs/io/image_io.h"

namespace facetool {

// One component as planar float channels (rows top to bottom), as the renderer's tensors want.
struct ComponentImage {
  std::string option;  // "--albedo", ... for messages
  std::string path;
  int width = 0, height = 0;
  int channels = 0;
  std::vector<float> planes;  // channels * height * width

  size_t plane_size() const { return static_cast<size_t>(width) * height; }
  float* plane(int c) { return planes.data() + c * plane_size(); }
  const float* plane(int c) const { return planes.data() + c * plane_size(); }
};

// File encodings, chosen by extension: .exr, .hdr and .pfm hold linear floats as they are;
// anything else (PNG, ...) is an encoded 8/16-bit image whose values are read scaled to [0, 1].
bool is_float_image_file(const std::string& path);

// A face crop file as linear RGB: 8/16-bit files decoded from sRGB, float files as they are; a
// NaN or infinite pixel is a facetool::Error naming the file.
RgbImage read_crop_image(const std::string& path);
// A face crop as planar linear RGB ([3][size*size]) at the network's size: 8/16-bit files are
// decoded from sRGB, float files taken as linear, then resized; a NaN or infinite pixel is a
// facetool::Error naming the file.
std::vector<float> read_planar_crop(const std::string& path, int size);

// Each reader takes the component's own channels from a multi-layer EXR when they are there
// (synth samples: albedo.R/G/B, normal.X/Y/Z, visibility.0..8, mask); otherwise it takes the
// file's channels by count. Throws facetool::Error naming the option and file for a missing or
// unreadable file or a wrong channel count.
//
// Albedo: RGB, RGBA (alpha ignored) or grey; encoded files are sRGB, decoded to linear.
ComponentImage read_albedo_image(const std::string& path);
// Normal: XYZ (or XYZA); encoded files hold (n + 1) / 2 per channel (docs/conventions.md).
ComponentImage read_normal_image(const std::string& path);
// Visibility: exactly 9 channels, the SH coefficients v_0..v_8.
ComponentImage read_visibility_image(const std::string& path);
// Mask: grey (or grey + alpha), or RGB(A) with R = G = B; values as stored, > 0.5 = rendered.
ComponentImage read_mask_image(const std::string& path);

// Fails naming the file, pixel and channel if `image` holds NaN or infinity where `rendered` is
// non-zero (or anywhere when `rendered` is empty); sets such values elsewhere to 0.
void check_finite(ComponentImage& image, const std::vector<char>& rendered);

}  // namespace facetool
