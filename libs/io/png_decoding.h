// PNG files read by libpng: the header, EXIF orientation and 8- or 16-bit pixels.
#pragma once

#include <memory>
#include <string>

#include "libs/io/image_file.h"

namespace facetool {

// Opens a PNG file and reads its header (ImageFileReader, image_file.h): format "png"; palettes
// expanded to RGB, grey of 1, 2 or 4 bits to 8, a transparent colour (tRNS) to an alpha channel;
// 8-bit files give bytes, 16-bit files floats (v / 65535); interlaced files de-interlaced; the
// values as stored (a gAMA or colour-profile chunk does not change them, as in OpenImageIO); the
// orientation from an eXIf chunk.
std::unique_ptr<ImageFileReader> open_png_file(const std::string& path, const std::string& kind = "image");

}  // namespace facetool
