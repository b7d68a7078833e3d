// Similarity fit to the template and the supersampled warp into the crop.
#include "libs/face/face_alignment.h"

#include <algorithm>
#include <cmath>

#include "libs/face/face_template.h"
#include "libs/image/border_fill.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"

namespace facetool {

FaceAlignment align_face(const Landmarks68& photo_landmarks, int crop_size, const CropFraming& framing) {
  check(crop_size > 0, "alignment: crop size must be positive (got ", crop_size, ")");
  const Landmarks68 target = canonical_template(crop_size, framing);
  std::vector<Point2> from, to;
  for (int i = 0; i < kLandmarkCount; ++i)
    if (is_inner_landmark(i)) {
      from.push_back(photo_landmarks[i]);
      to.push_back(target[i]);
    }
  FaceAlignment a;
  a.crop_size = crop_size;
  a.photo_to_crop = fit_similarity(from, to);
  for (int i = 0; i < kLandmarkCount; ++i) a.crop_landmarks[i] = a.photo_to_crop.apply(photo_landmarks[i]);
  return a;
}

namespace {

// warp_to_crop over C interleaved channels of a width x height image; the crop is planar.
template <int C>
std::vector<float> warp_interleaved(const float* pixels, int width, int height, const Similarity2& photo_to_crop,
                                    int crop_size, BorderFill border, std::vector<float>* coverage) {
  check(width > 0 && height > 0, "alignment: the photo is empty");
  const Similarity2 back = photo_to_crop.inverse();
  const int n = std::clamp(static_cast<int>(std::ceil(back.scale() - 1e-9)), 1, 8);
  const size_t plane = static_cast<size_t>(crop_size) * crop_size;
  std::vector<float> out(plane * C, 0.0f);
  std::vector<float> inside(plane, 0.0f);
  const float weight = 1.0f / static_cast<float>(n * n);
  const bool ring_mean = border == BorderFill::kRingMean;
  parallel_for(crop_size, 4, [&](int64_t begin, int64_t end) {
  for (int y = static_cast<int>(begin); y < end; ++y)
    for (int x = 0; x < crop_size; ++x) {
      float sum[C] = {};
      int count = 0;  // samples inside the photo
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Point2 p = back.apply({x - 0.5 + (i + 0.5) / n, y - 0.5 + (j + 0.5) / n});
          const bool in = p.x >= -0.5 && p.x <= width - 0.5 && p.y >= -0.5 && p.y <= height - 0.5;
          count += in;
          if (ring_mean && !in) continue;
          float s[C];
          sample_bilinear<C>(pixels, width, height, p.x, p.y, s);
          for (int k = 0; k < C; ++k) sum[k] += s[k];
        }
      const size_t at = static_cast<size_t>(y) * crop_size + x;
      inside[at] = static_cast<float>(count) * weight;
      if (!ring_mean)
        for (int k = 0; k < C; ++k) out[k * plane + at] = sum[k] * weight;
      else if (count > 0)
        for (int k = 0; k < C; ++k) out[k * plane + at] = sum[k] / static_cast<float>(count);
    }
  });
  if constexpr (C == 3)  // the ring mean is defined for colour crops (warp_to_crop)
    if (ring_mean) fill_outside_photo(out, inside, crop_size, crop_size);
  if (coverage) *coverage = std::move(inside);
  return out;
}

}  // namespace

std::vector<float> warp_to_crop(const RgbImage& photo, const Similarity2& photo_to_crop,
                                int crop_size, BorderFill border, std::vector<float>* coverage) {
  return warp_interleaved<3>(photo.pixels.data(), photo.width, photo.height, photo_to_crop, crop_size, border,
                             coverage);
}

std::vector<float> warp_plane_to_crop(const float* plane, int width, int height,
                                      const Similarity2& photo_to_crop, int crop_size) {
  return warp_interleaved<1>(plane, width, height, photo_to_crop, crop_size, BorderFill::kEdgeRepeat, nullptr);
}

}  // namespace facetool
