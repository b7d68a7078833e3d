// Resizing planar float images: area averaging when shrinking, bilinear when enlarging.
#pragma once

#include <vector>

namespace facetool {

// `src` holds `channels` planes of width x height (rows top to bottom). Each axis is resampled
// separately: shrinking averages the source pixels each output pixel covers (weighted by
// overlap, so no aliasing), enlarging interpolates bilinearly with pixel centres at i + 0.5
// (PyTorch's align_corners=False). Equal sizes copy.
std::vector<float> resize_planar(const std::vector<float>& src, int channels, int width,
                                 int height, int out_width, int out_height);

}  // namespace facetool
