// Drawing detected faces on a picture: box outlines and landmark dots (for contact sheets).
#pragma once

#include "libs/face/face_detector.h"

namespace facetool {

// Draws `face` on `image` (whose pixels are the photo's scaled by `scale`): the detector box in
// yellow, the 17 jaw points in cyan and the 51 inner points in red (linear colours).
void draw_face(RgbImage& image, const DetectedFace& face, double scale);

// `image` resized (box filter when shrinking, bilinear when growing) to `width` wide.
RgbImage resize_to_width(const RgbImage& image, int width);

}  // namespace facetool
