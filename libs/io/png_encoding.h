// Encoding 8-bit RGB and RGBA pictures as PNG bytes: rows filtered "up", deflated by libdeflate.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace facetool {

// The libdeflate level of the PNGs facetool writes (1: fastest; docs/performance.md has the
// measurement against zlib).
constexpr int kPngDeflateLevel = 1;

// A PNG of `width` x `height` 8-bit pixels with `channels` interleaved channels (3: RGB, 4: RGBA
// with straight alpha), rows top to bottom: the signature, IHDR, one IDAT (each row minus the row
// above, PNG's filter type 2, deflated at kPngDeflateLevel into a zlib stream) and IEND. No
// colour chunk: readers take the bytes as sRGB, as they did OpenImageIO's PNGs. `path` only names
// the file in error messages.
std::vector<unsigned char> encode_png8(const std::string& path, int width, int height, int channels,
                                       const uint8_t* pixels);

}  // namespace facetool
