// Paste-back: crop-sized results warped back to the photo's own resolution and pixel grid,
// inside the face mask, feathered at its edge.
#pragma once

#include <vector>

#include "libs/face/landmarks68.h"
#include "libs/image/similarity_transform.h"

namespace facetool {

// Where one face lands in the photo: a box of photo pixels and the blend weight in it.
struct PasteRegion {
  int x0 = 0, y0 = 0, width = 0, height = 0;  // box in the photo (clipped to it)
  std::vector<float> alpha;                   // width * height, in [0, 1]
  Similarity2 photo_to_crop;
  int crop_size = 0;
};

// alpha = clamp(d / feather, 0, 1), with d the signed distance (crop pixels) of the photo
// pixel's position in the crop to the mask polygon (crop coordinates): 1 deeper inside the
// mask than `feather` crop pixels, 0 outside it, a linear ramp between (feather 0: a hard edge).
PasteRegion paste_region(int photo_width, int photo_height, const Similarity2& photo_to_crop,
                         int crop_size, const std::vector<Point2>& crop_mask_polygon,
                         double feather);

// Blends `channels` planar crop images [C][S*S] into planar photo images [C][W*H] in place:
// photo = alpha * bilinear(crop at T(p)) + (1 - alpha) * photo.
void paste_channels(const PasteRegion& region, const float* crop_planar, int channels,
                    float* photo_planar, int photo_width, int photo_height);

}  // namespace facetool
