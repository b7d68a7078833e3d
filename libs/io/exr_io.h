// OpenEXR files with many named float channels and string metadata (via OpenImageIO).
#pragma once

#include <string>
#include <vector>

#include "libs/io/layered_image.h"

namespace facetool {

// How a channel is stored in the file (in memory every channel is float either way).
struct ExrStorage {
  // One flag per channel: true stores it as a 16-bit half float (10 bits of mantissa: a relative
  // rounding error of at most 2^-11, about 0.05 %), false as a 32-bit float. Empty: all 32-bit.
  std::vector<bool> half;
};

// Writes `image` as a run-length coded float OpenEXR, first under a temporary name, then renamed
// to `path`, so an interrupted write never leaves a partial file called `path`. Metadata become
// string attributes of the EXR header. Throws facetool::Error on failure.
void write_exr_atomically(const std::string& path, const LayeredImage& image);
// The bytes of `image` as an OpenEXR file, each channel stored as `storage` says (`path` names
// the file in errors); write_exr_atomically writes these bytes with every channel 32-bit.
std::vector<unsigned char> encode_exr(const std::string& path, const LayeredImage& image,
                                      const ExrStorage& storage = {});

// Reads every channel of an EXR (channel names as stored) and its string attributes whose name
// starts with `metadata_prefix` (all string attributes when empty).
LayeredImage read_exr(const std::string& path, const std::string& metadata_prefix = "");
// Like read_exr but reads only the header: size, channel names and metadata; no pixels.
LayeredImage read_exr_header(const std::string& path, const std::string& metadata_prefix = "");

}  // namespace facetool
