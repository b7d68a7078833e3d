// RGB image reading (libs/io/image_file.h) and PNG writing (png_encoding.h).
#include "libs/io/image_io.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>

#include "core/util/atomic_file.h"
#include "libs/io/image_file.h"
#include "libs/io/jpeg_check.h"
#include "libs/io/png_encoding.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/image_limits.h"
#include "core/util/memory_budget.h"
#include "core/util/stage_timer.h"

namespace facetool {

float linear_to_srgb(float linear) {
  const float x = std::clamp(linear, 0.0f, 1.0f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

namespace {
float float_from_bits(uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

uint8_t linear_to_srgb8_directly(float linear) {
  const float v = linear_to_srgb(linear);
  return static_cast<uint8_t>(std::lround((v == v ? v : 0.0f) * 255.0f));
}

}  // namespace

// Found by bisection over the ordered bit patterns of floats (the byte never decreases as the
// value grows). A bin is 2.4e-4 wide and the narrowest step, on sRGB's linear segment,
// 1 / (255 x 12.92) = 3.0e-4, so no bin holds two steps: checked here at start.
Srgb8Steps::Srgb8Steps() {
  const uint32_t one = 0x3f800000u;  // the bits of 1.0f
  for (int k = 1; k <= 255; ++k) {
    uint32_t low = 0, high = one;  // byte(low) < k <= byte(high)
    while (high - low > 1) {
      const uint32_t middle = low + (high - low) / 2;
      (linear_to_srgb8_directly(float_from_bits(middle)) >= k ? high : low) = middle;
    }
    thresholds[k - 1] = float_from_bits(high);
  }
  thresholds[255] = 2.0f;
  for (int i = 0; i < kBins; ++i) first[i] = linear_to_srgb8_directly(static_cast<float>(i) / kBins);
  bool one_step_per_bin = 255 - first[kBins - 1] <= 1;
  for (int i = 0; i + 1 < kBins; ++i) one_step_per_bin = one_step_per_bin && first[i + 1] - first[i] <= 1;
  if (!one_step_per_bin) {  // a programming error in linear_to_srgb: no byte could be trusted
    std::fputs("facetool: internal error: linear_to_srgb8's table has two steps in one bin\n", stderr);
    std::abort();
  }
}
const Srgb8Steps g_srgb8_steps;

float srgb_to_linear(float encoded) {
  const float x = std::clamp(encoded, 0.0f, 1.0f);
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

namespace {

// A compressed image cannot hold more than this many pixels per byte of file (deflate expands at
// most 1032:1 and a 1-bit PNG packs 8 pixels a byte; a JPEG needs at least one bit per 8x8
// block): a header claiming more is a damaged or cut-off file, refused before any allocation.
constexpr uint64_t kMaxPixelsPerCompressedByte = 16384;

}  // namespace

void check_image_header_plausible(const std::string& path, const std::string& format,
                                  int64_t width, int64_t height, uint64_t file_bytes) {
  if (format != "png" && format != "jpeg") return;
  const uint64_t pixels = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
  check(pixels <= (file_bytes + 64) * kMaxPixelsPerCompressedByte, "image '", path,
        "' says it is ", width, "x", height, " pixels but holds only ", file_bytes,
        " bytes, far too few for that many: the file is truncated or damaged; replace it");
}

namespace {

// Opens `path` (already checked to be a regular file of `file_bytes` bytes) and checks its header.
std::unique_ptr<ImageFileReader> open_image_for_reading(const std::string& path, uint64_t file_bytes,
                                                       const std::string& kind) {
  std::unique_ptr<ImageFileReader> reader = open_image_file(path, kind);
  const ImageFileHeader& header = reader->header();
  check_image_dimensions(path, header.width, header.height, header.channels);
  check_image_header_plausible(path, header.format, header.width, header.height, file_bytes);
  if (header.format == "jpeg")
    check(jpeg_is_complete(path), "image '", path, "' is a truncated JPEG: the file ends before ",
          "its image does (an interrupted download or copy?); replace it with a complete file");
  return reader;
}

RgbImage read_rgb(ImageFileReader& reader, const std::string& path, bool decode_srgb) {
  const ImageFileHeader& header = reader.header();
  const int channels = header.channels;
  const size_t count = static_cast<size_t>(header.width) * header.height;
  const std::string what = "reading image '" + path + "' of " + std::to_string(header.width) + "x" +
                           std::to_string(header.height) + " pixels";
  // 8-bit files are read as bytes and turned into floats by a table of their 256 values (v / 255,
  // decoded as below: the same result, without a power function per value); other files as
  // floats. The decoded channels and the RGB floats live at once.
  const bool bytes = header.eight_bit;
  const size_t raw_bytes = count * channels * (bytes ? 1 : sizeof(float));
  check_memory_budget(raw_bytes + count * 3 * sizeof(float), what);
  std::vector<float> raw;
  std::vector<uint8_t> raw8;
  RgbImage image;
  try {
    if (bytes)
      raw8.resize(count * channels);
    else
      raw.resize(count * channels);
    image.pixels.resize(count * 3);
  } catch (const std::bad_alloc&) {
    throw out_of_memory(what, raw_bytes + count * 3 * sizeof(float));
  }
  if (bytes)
    reader.read_bytes(raw8.data());
  else
    reader.read_floats(raw.data());
  image.width = static_cast<int>(header.width);
  image.height = static_cast<int>(header.height);
  if (bytes) {
    std::array<float, 256> table;
    for (int k = 0; k < 256; ++k) {
      table[k] = static_cast<float>(k) * (1.0f / 255.0f);
      if (decode_srgb) table[k] = srgb_to_linear(table[k]);
    }
    for (size_t p = 0; p < count; ++p)
      for (int c = 0; c < 3; ++c) image.pixels[p * 3 + c] = table[raw8[p * channels + (channels >= 3 ? c : 0)]];
    return image;
  }
  for (size_t p = 0; p < count; ++p)
    for (int c = 0; c < 3; ++c) {
      const int source_channel = channels >= 3 ? c : 0;  // grey (+ alpha) replicates channel 0
      const float value = raw[p * channels + source_channel];
      check(std::isfinite(value), "image '", path, "' holds a NaN or infinite value at pixel (",
            p % header.width, ", ", p / header.width, ") channel ", source_channel,
            "; fix or regenerate the file");
      image.pixels[p * 3 + c] = decode_srgb ? srgb_to_linear(value) : value;
    }
  return image;
}

}  // namespace

RgbImage read_rgb_image(const std::string& path, bool decode_srgb) {
  const uint64_t file_bytes = check_regular_input_file(path, kMaxImageFileBytes, "image");
  protect_input_file(path);
  std::unique_ptr<ImageFileReader> reader = open_image_for_reading(path, file_bytes, "image");
  return read_rgb(*reader, path, decode_srgb);
}

RgbImage read_rgb_image_as_encoded(const std::string& path, int& orientation, const char* kind) {
  const uint64_t file_bytes = check_regular_input_file(path, kMaxImageFileBytes, kind);
  protect_input_file(path);
  std::unique_ptr<ImageFileReader> reader = open_image_for_reading(path, file_bytes, kind);
  orientation = reader->header().orientation;
  return read_rgb(*reader, path, !reader->header().floating);
}

std::vector<unsigned char> encode_png(const std::string& path, const RgbImage& rgb,
                                      bool encode_srgb) {
  StageTimer timer("encode");  // the 8-bit (sRGB) conversion and the PNG compression
  check(rgb.width > 0 && rgb.height > 0, "cannot write '", path, "': the image is empty");
  std::vector<uint8_t> bytes(rgb.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    if (encode_srgb) {
      bytes[i] = linear_to_srgb8(rgb.pixels[i]);
      continue;
    }
    bytes[i] = unit_to_byte(rgb.pixels[i]);
  }
  return encode_png8(path, rgb.width, rgb.height, 3, bytes.data());
}

void write_png_atomically(const std::string& path, const RgbImage& rgb, bool encode_srgb) {
  const std::vector<unsigned char> encoded = encode_png(path, rgb, encode_srgb);
  write_file_atomically(path, encoded.data(), encoded.size());
}

RgbImage rgb_from_planar(const float* planar, int width, int height) {
  RgbImage image;
  image.width = width;
  image.height = height;
  const size_t plane = static_cast<size_t>(width) * height;
  image.pixels.resize(plane * 3);
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) image.pixels[p * 3 + c] = planar[c * plane + p];
  return image;
}

std::vector<float> planar_from_rgb(const RgbImage& image) {
  const size_t plane = static_cast<size_t>(image.width) * image.height;
  std::vector<float> planar(plane * 3);
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) planar[c * plane + p] = image.pixels[p * 3 + c];
  return planar;
}

}  // namespace facetool
