// RGB image reading and PNG writing through OpenImageIO.
#include "core/io/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/util/atomic_file.h"
#include "core/io/image_encoding.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/image_limits.h"
#include "core/util/stage_timer.h"

namespace facetool {

namespace OIIO = OIIO_NAMESPACE;

float linear_to_srgb(float linear) {
  const float x = std::clamp(linear, 0.0f, 1.0f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgb_to_linear(float encoded) {
  const float x = std::clamp(encoded, 0.0f, 1.0f);
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

RgbImage read_rgb_image(const std::string& path, bool decode_srgb) {
  check_regular_input_file(path, kMaxImageFileBytes, "image");
  auto input = OIIO::ImageInput::open(path);
  if (!input)
    fail("cannot read image '", path, "': ", OIIO::geterror(),
         " (check that the file is a complete image OpenImageIO can read)");
  const OIIO::ImageSpec& spec = input->spec();
  check_image_dimensions(path, spec.width, spec.height, spec.nchannels);
  const int channels = spec.nchannels;
  std::vector<float> raw(static_cast<size_t>(spec.width) * spec.height * channels);
  if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, raw.data()))
    fail("cannot read the pixels of image '", path, "': ", input->geterror(),
         " (the file is truncated or damaged: replace it)");
  input->close();
  RgbImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.pixels.resize(static_cast<size_t>(spec.width) * spec.height * 3);
  const size_t count = static_cast<size_t>(spec.width) * spec.height;
  for (size_t p = 0; p < count; ++p)
    for (int c = 0; c < 3; ++c) {
      const int source_channel = channels >= 3 ? c : 0;  // grey (+ alpha) replicates channel 0
      const float value = raw[p * channels + source_channel];
      check(std::isfinite(value), "image '", path, "' holds a NaN or infinite value at pixel (",
            p % spec.width, ", ", p / spec.width, ") channel ", source_channel,
            "; fix or regenerate the file");
      image.pixels[p * 3 + c] = decode_srgb ? srgb_to_linear(value) : value;
    }
  return image;
}

std::vector<unsigned char> encode_png(const std::string& path, const RgbImage& rgb,
                                      bool encode_srgb) {
  StageTimer timer("encode");  // the 8-bit (sRGB) conversion and the PNG compression
  check(rgb.width > 0 && rgb.height > 0, "cannot write '", path, "': the image is empty");
  std::vector<uint8_t> bytes(rgb.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    const float v = encode_srgb ? linear_to_srgb(rgb.pixels[i])
                                : std::min(1.0f, std::max(0.0f, rgb.pixels[i]));
    bytes[i] = static_cast<uint8_t>(std::lround((v == v ? v : 0.0f) * 255.0f));
  }
  const OIIO::ImageSpec spec(rgb.width, rgb.height, 3, OIIO::TypeDesc::UINT8);
  return encode_image(path, "png", spec, OIIO::TypeDesc::UINT8, bytes.data());
}

void write_png_atomically(const std::string& path, const RgbImage& rgb, bool encode_srgb) {
  const std::vector<unsigned char> encoded = encode_png(path, rgb, encode_srgb);
  write_file_atomically(path, encoded.data(), encoded.size());
}

}  // namespace facetool
