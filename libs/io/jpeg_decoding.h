// JPEG files read by libjpeg-turbo: the header, EXIF orientation and 8-bit pixels.
#pragma once

#include <memory>
#include <string>

#include "libs/io/image_file.h"

namespace facetool {

// Opens a JPEG file and reads its header (ImageFileReader, image_file.h): format "jpeg", 8-bit,
// 1 channel (grey) or 3 (RGB; CMYK and YCCK files are turned into RGB, their ink values taken as
// stored inverted, as Adobe writes them); the orientation from the EXIF block. libjpeg's defaults
// (accurate integer DCT, smooth chroma upsampling), as OpenImageIO decodes them. Warnings on
// damaged data are not printed (a cut-off file is refused by jpeg_check.h before decoding).
std::unique_ptr<ImageFileReader> open_jpeg_file(const std::string& path, const std::string& kind = "image");

}  // namespace facetool
