// OpenEXR files with many named float channels and string metadata (via OpenImageIO).
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "libs/io/layered_image.h"

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

// Writes `image` as a run-length coded float OpenEXR, first under a temporary name, then renamed
// to `path`, so an interrupted write never leaves a partial file called `path`. Metadata become
// string attributes of the EXR header. Throws facetool::Error on failure.
void write_exr_atomically(const std::string& path, const LayeredImage& image);
// The bytes write_exr_atomically writes (`path` names the file in errors).
std::vector<unsigned char> encode_exr(const std::string& path, const LayeredImage& image);
// The bytes of a width x height OpenEXR file of `channels`, read where they lie (no planar copy
// is made), each stored as its `half` flag says, with string `metadata`.
std::vector<unsigned char> encode_exr(const std::string& path, int width, int height,
                                      const std::vector<ExrChannel>& channels,
                                      const std::vector<std::pair<std::string, std::string>>& metadata);

// Reads every channel of an EXR (channel names as stored) and its string attributes whose name
// starts with `metadata_prefix` (all string attributes when empty).
LayeredImage read_exr(const std::string& path, const std::string& metadata_prefix = "");
// Like read_exr but reads only the header: size, channel names and metadata; no pixels.
LayeredImage read_exr_header(const std::string& path, const std::string& metadata_prefix = "");

}  // namespace facetool
