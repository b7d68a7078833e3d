// RGBA PNG writing: encoded in memory (png_encoding.h), then written atomically.
#include "libs/face/rgba_png.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/stage_timer.h"
#include "libs/io/png_encoding.h"

namespace facetool {

std::vector<unsigned char> encode_rgba_png(const std::string& path, const RgbImage& rgb,
                                           const std::vector<float>& alpha, bool encode_srgb) {
  const size_t count = static_cast<size_t>(rgb.width) * rgb.height;
  check(count > 0 && alpha.size() == count, "cannot write '", path,
        "': empty image or alpha of the wrong size");
  StageTimer timer("encode");  // 8-bit conversion and compression
  std::vector<uint8_t> bytes(count * 4);
  for (size_t p = 0; p < count; ++p) {
    for (int c = 0; c < 3; ++c) {
      const float v = rgb.pixels[p * 3 + c];
      bytes[p * 4 + c] = encode_srgb ? linear_to_srgb8(v) : unit_to_byte(v);
    }
    bytes[p * 4 + 3] = unit_to_byte(alpha[p]);
  }
  return encode_png8(path, rgb.width, rgb.height, 4, bytes.data());
}

void write_rgba_png_atomically(const std::string& path, const RgbImage& rgb,
                               const std::vector<float>& alpha, bool encode_srgb) {
  const std::vector<unsigned char> encoded = encode_rgba_png(path, rgb, alpha, encode_srgb);
  write_file_atomically(path, encoded.data(), encoded.size());
}

}  // namespace facetool
