// Alignment of a detected face to the synthetic framing: the least-squares similarity from its
// inner landmarks to the canonical template, and the warp of the photo into the crop.
#pragma once

#include <algorithm>
#include <vector>

#include "libs/face/landmarks68.h"
#include "libs/image/crop_framing.h"
#include "libs/image/similarity_transform.h"
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

// warp_to_crop of one plane of `width` x `height` values (edges repeated): the guided
// paste-back's luma.
std::vector<float> warp_plane_to_crop(const float* plane, int width, int height,
                                      const Similarity2& photo_to_crop, int crop_size);

// Bilinear sample of C interleaved channels at (x, y) (pixel centres at integers, edges
// clamped); inline, as the warps call it for every sample.
template <int C>
inline void sample_bilinear(const float* pixels, int width, int height, double x, double y, float out[C]) {
  x = std::clamp(x, 0.0, width - 1.0);
  y = std::clamp(y, 0.0, height - 1.0);
  const int x0 = std::min(static_cast<int>(x), width - 1);
  const int y0 = std::min(static_cast<int>(y), height - 1);
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const float* a = pixels + (static_cast<size_t>(y0) * width + x0) * C;
  const float* b = pixels + (static_cast<size_t>(y0) * width + x1) * C;
  const float* c = pixels + (static_cast<size_t>(y1) * width + x0) * C;
  const float* d = pixels + (static_cast<size_t>(y1) * width + x1) * C;
  for (int k = 0; k < C; ++k)
    out[k] = (a[k] * (1 - fx) + b[k] * fx) * (1 - fy) + (c[k] * (1 - fx) + d[k] * fx) * fy;
}

inline void sample_rgb_bilinear(const RgbImage& image, double x, double y, float out[3]) {
  sample_bilinear<3>(image.pixels.data(), image.width, image.height, x, y, out);
}

}  // namespace facetool
