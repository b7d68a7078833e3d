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
// the guide's [0, 1] scale (docs/photos.md, "Guided upsampling").
struct GuidedUpsampling {
  int radius = 1;
  double epsilon = 1e-3;
};

// The guide of one face: Rec. 709 luma of the sRGB-encoded photo ([0, 1]; encoded values, so that
// edges in shadows count as much as a viewer sees them) over the photo pixels its crop and its
// paste region reach (a box, clipped to the photo), and the same brought into the crop the way
// the photo was (warp_to_crop: area averaged, edge repeat beyond the photo).
struct FaceGuide {
  int x0 = 0, y0 = 0, width = 0, height = 0;  // the box in the photo
  std::vector<float> photo;                   // [width * height]
  std::vector<float> crop;                    // [S * S]
};
FaceGuide face_guide(const RgbImage& photo, const PasteRegion& region);

// Like paste_channels (paste_back.h), with guided upsampling (He and Sun, "Fast Guided Filter",
// 2015): the guided filter's coefficients a, b (libs/image/guided_filter.h) are fitted on the
// crop's grid between guide.crop and the crop's maps, sampled bilinearly at each photo pixel like
// the maps themselves would be, and applied to the photo's own guide: value = a * guide + b.
// Where the map is a linear function of the guide within a window, the photo's edges come
// through at its resolution; where the guide is flat, the result is the map's local mean.
// `unit_vectors`: the 3 channels are a vector per pixel, renormalised (normals); otherwise the
// result is clamped to [clamp_lo, clamp_hi] (albedo: 0, 1). `guide` is face_guide(photo, region).
void paste_channels_guided(const PasteRegion& region, const float* crop_planar, int channels,
                           const FaceGuide& guide, float* photo_planar, int photo_width,
                           int photo_height, bool unit_vectors, float clamp_lo, float clamp_hi,
                           const GuidedUpsampling& settings = {});

}  // namespace facetool
