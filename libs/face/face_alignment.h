// Alignment of a detected face to the synthetic framing: the least-squares similarity from its
// inner landmarks to the canonical template, and the warp of the photo into the crop.
#pragma once

#include <vector>

#include "libs/face/point2.h"
#include "libs/image/crop_framing.h"
#include "libs/face/similarity_transform.h"
#include "libs/io/image_io.h"

namespace facetool {

struct FaceAlignment {
  int crop_size = 128;
  Similarity2 photo_to_crop;     // everything goes back through its inverse
  Landmarks68 crop_landmarks{};  // the photo's landmarks mapped into the crop
};

// Fits the similarity on the 51 inner points (is_inner_landmark) only: the jaw line slides
// with the view and would pull the fit. The target is canonical_template(crop_size, framing).
FaceAlignment align_face(const Landmarks68& photo_landmarks, int crop_size,
                         const CropFraming& framing = CropFraming{});

// The crop: planar linear RGB [3][S*S]. Each crop pixel averages n x n bilinear samples of the
// photo spread over its footprint (n = ceil(photo pixels per crop pixel), at most 8), so large
// photos do not alias. Outside the photo (sample positions beyond its pixels' outer edges), by
// `border`: kEdgeRepeat repeats the nearest edge pixel; kRingMean averages only the samples
// inside and fills the rest with fill_outside_photo (libs/image/border_fill.h). `coverage`, when
// given, receives the fraction of each crop pixel's samples inside the photo [S*S].
std::vector<float> warp_to_crop(const RgbImage& photo, const Similarity2& photo_to_crop,
                                int crop_size, BorderFill border = BorderFill::kEdgeRepeat,
                                std::vector<float>* coverage = nullptr);

// Bilinear sample of interleaved RGB at (x, y) (pixel centres at integers, edges clamped).
void sample_rgb_bilinear(const RgbImage& image, double x, double y, float out[3]);

}  // namespace facetool
