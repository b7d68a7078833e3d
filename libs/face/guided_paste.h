// Paste-back guided by the photo: crop-level maps brought to the photo's resolution by guided
// upsampling (the fast guided filter), so their edges follow the photo's (docs/photos.md).
#pragma once

#include <vector>

#include "libs/face/paste_back.h"
#include "libs/io/image_io.h"

namespace facetool {

// How crop-level maps are brought to the photo's resolution (`infer --upsample`).
enum class Upsample { kBilinear, kGuided };

// The guided filter's settings on the crop's grid: window radius in crop pixels and epsilon on
// the guide's [0, 1] scale (docs/photos.md, "Paste-back").
struct GuidedUpsampling {
  int radius = 1;
  double epsilon = 1e-3;
};

// The guide: Rec. 709 luma of the sRGB-encoded photo ([0, 1], one plane of width * height);
// encoded values, so that edges in shadows count as much as a viewer sees them.
std::vector<float> photo_guide(const RgbImage& photo);

// The guide brought into the region's crop the way the photo was (warp_to_crop, area averaged;
// edge repeat): [S*S]. Reads only the part of the guide the crop covers.
std::vector<float> crop_guide(const std::vector<float>& guide, int photo_width, int photo_height,
                              const PasteRegion& region);

// Like paste_channels (paste_back.h), with guided upsampling (He and Sun, "Fast Guided Filter",
// 2015): with the guide in the crop (`crop_guide_planar`, crop_guide(...)), the guided filter's
// coefficients a, b (libs/image/guided_filter.h) are fitted there
// between it and the crop's maps, sampled bilinearly at each photo pixel like the maps
// themselves would be, and applied to the photo's own guide: value = a * guide + b. Where the
// map is a linear function of the guide within a window, the photo's edges come through at its
// resolution; where the guide is flat, the result is the map's local mean. `unit_vectors`: the 3
// channels are a vector per pixel, renormalised (normals); otherwise the result is clamped to
// [clamp_lo, clamp_hi] (albedo: 0, 1). `guide` is photo_guide(photo).
void paste_channels_guided(const PasteRegion& region, const float* crop_planar, int channels,
                           const std::vector<float>& crop_guide_planar,
                           const std::vector<float>& guide, float* photo_planar, int photo_width,
                           int photo_height, bool unit_vectors, float clamp_lo, float clamp_hi,
                           const GuidedUpsampling& settings = {});

}  // namespace facetool
