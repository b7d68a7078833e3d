// Reading ordinary images (HDR, EXR, PNG, JPEG, ...) as float RGB and writing 8-bit PNGs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace facetool {

// An interleaved RGB float image, rows top to bottom.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  // width * height * 3

  float* at(int x, int y) { return pixels.data() + (static_cast<size_t>(y) * width + x) * 3; }
  const float* at(int x, int y) const {
    return pixels.data() + (static_cast<size_t>(y) * width + x) * 3;
  }
};

// The one conversion between interleaved RGB and planar [3][width*height] values (rows top to
// bottom): `planar` holds 3 planes of width * height.
RgbImage rgb_from_planar(const float* planar, int width, int height);
std::vector<float> planar_from_rgb(const RgbImage& image);

// Reads JPEG, PNG and any format OpenImageIO knows (image_file.h). Grey images are replicated to RGB, alpha is dropped (the
// colours are taken as stored, not multiplied by alpha). A truncated JPEG is refused, and so is
// a header claiming more pixels than the file can hold; the pixel memory is checked against what
// the machine has (memory_budget.h: "out of memory while reading image ...").
// Values are as stored: linear radiance for HDR/EXR; for 8-bit formats (sRGB-encoded) pass
// `decode_srgb` to convert them to linear. Throws facetool::Error naming the file, also for
// a NaN or infinite value (naming the pixel) and for a header beyond core/util/image_limits.h.
RgbImage read_rgb_image(const std::string& path, bool decode_srgb = false);
// read_rgb_image deciding the decoding by the file, as photos are read: integer samples (8- and
// 16-bit) taken as sRGB and decoded to linear, floating-point samples (EXR, HDR) as they are; the
// file's EXIF orientation (1-8, 1 where it has none) in `orientation`, not applied. `kind` names
// the file in messages ("photo 'a.jpg' ...").
RgbImage read_rgb_image_as_encoded(const std::string& path, int& orientation, const char* kind = "image");

// Refuses (facetool::Error naming the file) a PNG or JPEG header that claims more pixels than a
// file of `file_bytes` bytes can hold: a cut-off or damaged file, caught before its pixels are
// allocated. Other formats (EXR, HDR, ...) pass.
void check_image_header_plausible(const std::string& path, const std::string& format,
                                  int64_t width, int64_t height, uint64_t file_bytes);

// Rec. 709 weighted sum of three channels: the luminance of linear RGB (the luma of sRGB-encoded
// values). The detector's engine spells it out instead: its AVX2 copy must not define code that
// the portable program shares (libs/face/face_detector_engine_avx2.cpp).
inline float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

// sRGB transfer functions on linear values in [0, 1] (inputs are clamped).
float linear_to_srgb(float linear);
float srgb_to_linear(float encoded);
// The steps of linear_to_srgb8, computed once from linear_to_srgb (image_io.cpp):
// thresholds[k] is the smallest float in [0, 1] whose byte is k + 1 or more, thresholds[255] a
// sentinel above 1; first[i] the byte at the value i / kBins. No bin holds more than one step.
struct Srgb8Steps {
  static constexpr int kBins = 4096;
  float thresholds[256];
  uint8_t first[kBins];
  Srgb8Steps();
};
extern const Srgb8Steps g_srgb8_steps;

// lround(255 * linear_to_srgb(linear)), 0 for NaN: the same byte as computing it, read from a
// table of 4,096 bins over [0, 1] and the 255 linear values where the byte steps (computed once
// from linear_to_srgb itself), several times faster than the power function per pixel. Always
// inlined (it runs per value in the writers' loops), so no copy of it is compiled for AVX2 in
// the detector's engine and shared with the portable program.
[[gnu::always_inline]] inline uint8_t linear_to_srgb8(float linear) {
  if (!(linear > 0.0f)) return 0;  // NaN, zero and below
  if (linear >= 1.0f) return 255;
  // linear * kBins is exact (a power of two), so the bin's lower edge is at or below `linear`;
  // the value's byte is its bin's first byte or the next.
  const int byte = g_srgb8_steps.first[static_cast<int>(linear * Srgb8Steps::kBins)];
  return static_cast<uint8_t>(byte + (linear >= g_srgb8_steps.thresholds[byte]));  // no branch
}
// lround(255 * v) of v clamped to [0, 1], 0 for NaN: a value written as a byte as it is (data
// pictures such as normals as (n + 1) / 2, alpha). The same byte, with the rounding done by a
// truncation and an exact comparison of the remainder instead of a call to lround.
inline uint8_t unit_to_byte(float v) {
  const float x = (v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f) * 255.0f;  // NaN fails v > 0
  const int whole = static_cast<int>(x);
  return static_cast<uint8_t>(whole + (x - static_cast<float>(whole) >= 0.5f));
}

// Writes `rgb` (linear values, clamped to [0, 1], sRGB-encoded on the way) as an 8-bit PNG,
// atomically (temporary name, then rename). With encode_srgb = false the values are written as
// they are (for data pictures such as normals encoded as (n + 1) / 2); NaN becomes 0.
void write_png_atomically(const std::string& path, const RgbImage& rgb, bool encode_srgb = true);
// The bytes write_png_atomically writes (`path` names the file in errors).
std::vector<unsigned char> encode_png(const std::string& path, const RgbImage& rgb,
                                      bool encode_srgb = true);

}  // namespace facetool
