// OpenEXR files of many named float channels with string metadata: written, atomically, and read.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "libs/io/exr_encoding.h"
#include "libs/io/layered_image.h"

namespace facetool {

// Writes `image` as a run-length coded float OpenEXR, first under a temporary name, then renamed
// to `path`, so an interrupted write never leaves a partial file called `path`. Metadata become
// string attributes of the EXR header. Throws facetool::Error on failure.
void write_exr_atomically(const std::string& path, const LayeredImage& image);
// The bytes write_exr_atomically writes (`path` names the file in errors): encode_exr
// (exr_encoding.h) of the image's planes as 32-bit floats.
std::vector<unsigned char> encode_exr(const std::string& path, const LayeredImage& image);

// Reads every channel of an EXR (channel names as stored) and its string attributes whose name
// starts with `metadata_prefix` (all string attributes when empty, except the ones OpenImageIO
// adds to describe the file: "compression" and "oiio:" names), so an image read can be written
// again as it is.
LayeredImage read_exr(const std::string& path, const std::string& metadata_prefix = "");
// Like read_exr but reads only the header: size, channel names and metadata; no pixels.
LayeredImage read_exr_header(const std::string& path, const std::string& metadata_prefix = "");

}  // namespace facetool
