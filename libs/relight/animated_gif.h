// Animated GIF files written with OpenImageIO (built with giflib on Debian), atomically.
#pragma once

#include <string>
#include <vector>

#include "libs/io/image_io.h"

namespace facetool {

// Writes `frames` (linear RGB, all the same size) as an 8-bit sRGB animated GIF that loops for
// ever at `frames_per_second`. Written to a temporary name and renamed, so a failure leaves
// nothing at `path`. Throws facetool::Error naming the file when OpenImageIO cannot write GIF.
void write_animated_gif(const std::string& path, const std::vector<RgbImage>& frames,
                        int frames_per_second);

}  // namespace facetool
