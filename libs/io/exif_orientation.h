// The orientation tag of an EXIF block (JPEG's APP1 segment, PNG's eXIf chunk).
#pragma once

#include <cstddef>
#include <cstdint>

namespace facetool {

// The value of tag 0x0112 (Orientation) in the first image file directory of `tiff`, an EXIF
// block from its TIFF header ("II*\0" or "MM\0*") on; 1 when the block is damaged, has no such
// tag, or holds a value outside 1-8 (apply_exif_orientation in libs/face/photo_reader.h).
int exif_orientation(const uint8_t* tiff, size_t size);

}  // namespace facetool
