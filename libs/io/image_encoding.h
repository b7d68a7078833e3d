// Encoding a picture into bytes in memory (OpenImageIO through an in-memory IOProxy).
#pragma once

#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

namespace facetool {

// zlib level and row filter of the PNGs facetool writes (1: fastest; libpng's PNG_FILTER_UP,
// each row minus the one above; docs/performance.md has the measurement).
constexpr int kPngCompressionLevel = 1;
constexpr int kPngRowFilter = 0x20;

// Encodes `pixels` (interleaved, of `type`, as `spec` says) with OpenImageIO's writer for
// `format` ("png", "openexr") into bytes, so that the caller can write them with every error
// checked (write_file_atomically). `path` only names the file in error messages. PNGs get
// kPngCompressionLevel and kPngRowFilter unless `spec` sets "png:compressionLevel" or
// "png:filter".
std::vector<unsigned char> encode_image(const std::string& path, const char* format,
                                        const OIIO_NAMESPACE::ImageSpec& spec,
                                        OIIO_NAMESPACE::TypeDesc type, const void* pixels);

}  // namespace facetool
