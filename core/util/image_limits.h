// The largest image facetool reads, checked from the file's header before any pixel memory.
#pragma once

#include <cstdint>
#include <string>

#include "core/util/error.h"

namespace facetool {

// 32768 pixels a side, 2^28 pixels (16384 x 16384), 64 channels and 2^30 channel values (4 GiB
// as floats): far above any face crop, environment map or training sample, and below what a
// header could make us allocate (documented in docs/input-limits.md).
constexpr int64_t kMaxImageSide = 32768;
constexpr uint64_t kMaxImagePixels = uint64_t{1} << 28;
constexpr int64_t kMaxImageChannels = 64;
constexpr uint64_t kMaxImageValues = uint64_t{1} << 30;

// Throws facetool::Error "<what> '<path>' ..." when the header's size is empty or too large.
// `what` names the kind of file, e.g. "image", "EXR", "environment map".
inline void check_image_dimensions(const std::string& path, int64_t width, int64_t height,
                                   int64_t channels, const std::string& what = "image") {
  check(width > 0 && height > 0 && channels > 0, what, " '", path, "' is empty (", width, "x",
        height, ", ", channels, " channels); replace it with a valid file");
  const uint64_t pixels = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
  check(width <= kMaxImageSide && height <= kMaxImageSide && channels <= kMaxImageChannels &&
            pixels <= kMaxImagePixels &&
            pixels * static_cast<uint64_t>(channels) <= kMaxImageValues,
        what, " '", path, "' says it is ", width, "x", height, " with ", channels,
        " channels, more than facetool reads (at most ", kMaxImageSide, " pixels a side, ",
        kMaxImagePixels, " pixels, ", kMaxImageChannels, " channels, ", kMaxImageValues,
        " values); the file is damaged or too large: shrink it first");
}

}  // namespace facetool
