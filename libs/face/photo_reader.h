// Reading a photo for detection: JPEG, PNG or any format OpenImageIO reads, EXIF orientation applied.
#pragma once

#include <string>

#include "libs/io/image_io.h"

namespace facetool {

// Linear RGB, upright: the EXIF/TIFF Orientation tag (1-8) is applied. Integer formats (8 or
// 16 bit) are taken as sRGB-encoded and decoded; float formats (EXR, HDR) as linear. Grey is
// replicated, alpha dropped. Throws facetool::Error naming the file.
RgbImage read_photo(const std::string& path);

// The Orientation tag's transform applied to `image` (1: unchanged; 2-8 as in EXIF).
RgbImage apply_exif_orientation(const RgbImage& image, int orientation);

}  // namespace facetool
