// Encoding float and half channels as OpenEXR bytes: one part, scan lines, run-length coded.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace facetool {

// One channel to encode, read in place: pixel p's value is data[p * stride] (stride 1: a plane;
// 3: one channel of an interleaved RGB image).
struct ExrChannel {
  std::string name;
  const float* data = nullptr;
  size_t stride = 1;
  // Stored as a 16-bit half float (10 bits of mantissa: a relative rounding error of at most
  // 2^-11, about 0.05 %) instead of a 32-bit float.
  bool half = false;
};

// The bytes of a width x height OpenEXR file (version 2, single-part scan lines, RLE compression:
// one scan line per chunk, each chunk stored raw where run-length coding would not make it
// smaller) holding `channels`, read where they lie, each stored as its `half` flag says (halves
// rounded as Imath::half rounds), and `metadata` as string attributes of the header. The header
// lists the channels sorted by name, as the format requires; readers give them back by name.
// `path` only names the file in error messages. Throws facetool::Error on empty or unnamed
// channels, repeated names, names longer than the format's 255 bytes, or an image larger than
// facetool reads (core/util/image_limits.h).
std::vector<unsigned char> encode_exr(const std::string& path, int width, int height,
                                      const std::vector<ExrChannel>& channels,
                                      const std::vector<std::pair<std::string, std::string>>& metadata);

// OpenEXR's run-length code of `size` bytes, after its two preparation steps (the bytes split
// into the even- and the odd-numbered halves, then each byte replaced by its difference to the
// one before plus 128): the stream a reader of compression RLE expands back into `bytes`.
// Exposed for the tests.
std::vector<unsigned char> exr_rle_compress(const unsigned char* bytes, size_t size);

}  // namespace facetool
