// The largest image facetool reads, checked from the file's header before any pixel memory.
#pragma once

#include <cstdint>
#include <string>

#include "core/util/error.h"

namespace facetool {

// 2^28 pixels (16384 x 16384) and 2^30 channel values (4 GiB as floats): far above any face
// crop, environment map or training sample, and below what a header could make us allocate.
constexpr uint64_t kMaxImagePixels = uint64_t{1} << 28;
constexpr uint64_t kMaxImageValues = uint64_t{1} << 30;

// Throws facetool::Error naming `what` and `path` when the header's size is empty or too large.
inline void check_image_dimensions(const std::string& path, int64_t width, int64_t height,
                                   int64_t channels, const char* what = "image") {
  check(width > 0 && height > 0 && channels > 0, what, " '", path, "' is empty (", width, "x",
        height, ", ", channels, " channels)");
  const uint64_t pixels = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
  check(pixels <= kMaxImagePixels && pixels * static_cast<uint64_t>(channels) <= kMaxImageValues,
        what, " '", path, "' claims ", width, "x", height, " pixels with ", channels,
        " channels, more than facetool reads (", kMaxImagePixels, " pixels, ", kMaxImageValues,
        " values); the file is damaged or not meant for facetool");
}

}  // namespace facetool
