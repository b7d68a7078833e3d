// Encoding a picture into bytes in memory (OpenImageIO through an in-memory IOProxy).
#pragma once

#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

namespace facetool {

// Encodes `pixels` (interleaved, of `type`, as `spec` says) with OpenImageIO's writer for
// `format` ("openexr", "jpeg", ...) into bytes, so that the caller can write them with every error
// checked (write_file_atomically). `path` only names the file in error messages. facetool's PNGs
// are written by encode_png8 (png_encoding.h).
std::vector<unsigned char> encode_image(const std::string& path, const char* format,
                                        const OIIO_NAMESPACE::ImageSpec& spec,
                                        OIIO_NAMESPACE::TypeDesc type, const void* pixels);

}  // namespace facetool
