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

void sample_rgb_bilinear(const RgbImage& image, double x, double y, float out[3]) {
  x = std::clamp(x, 0.0, image.width - 1.0);
  y = std::clamp(y, 0.0, image.height - 1.0);
  const int x0 = std::min(static_cast<int>(x), image.width - 1);
  const int y0 = std::min(static_cast<int>(y), image.height - 1);
  const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const float *a = image.at(x0, y0), *b = image.at(x1, y0), *c = image.at(x0, y1),
              *d = image.at(x1, y1);
  for (int k = 0; k < 3; ++k)
    out[k] = (a[k] * (1 - fx) + b[k] * fx) * (1 - fy) + (c[k] * (1 - fx) + d[k] * fx) * fy;
}

std::vector<float> warp_to_crop(const RgbImage& photo, const Similarity2& photo_to_crop,
                                int crop_size, BorderFill border, std::vector<float>* coverage) {
  check(photo.width > 0 && photo.height > 0, "alignment: the photo is empty");
  const Similarity2 back = photo_to_crop.inverse();
  const int n = std::clamp(static_cast<int>(std::ceil(back.scale() - 1e-9)), 1, 8);
  const size_t plane = static_cast<size_t>(crop_size) * crop_size;
  std::vector<float> out(plane * 3, 0.0f);
  std::vector<float> inside(plane, 0.0f);
  const float weight = 1.0f / static_cast<float>(n * n);
  const bool ring_mean = border == BorderFill::kRingMean;
  parallel_for(crop_size, 4, [&](int64_t begin, int64_t end) {
  for (int y = static_cast<int>(begin); y < end; ++y)
    for (int x = 0; x < crop_size; ++x) {
      float sum[3] = {0, 0, 0};
      int count = 0;  // samples inside the photo
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Point2 p = back.apply({x - 0.5 + (i + 0.5) / n, y - 0.5 + (j + 0.5) / n});
          const bool in = p.x >= -0.5 && p.x <= photo.width - 0.5 && p.y >= -0.5 && p.y <= photo.height - 0.5;
          count += in;
          if (ring_mean && !in) continue;
          float s[3];
          sample_rgb_bilinear(photo, p.x, p.y, s);
          for (int k = 0; k < 3; ++k) sum[k] += s[k];
        }
      const size_t at = static_cast<size_t>(y) * crop_size + x;
      inside[at] = static_cast<float>(count) * weight;
      if (!ring_mean)
        for (int k = 0; k < 3; ++k) out[k * plane + at] = sum[k] * weight;
      else if (count > 0)
        for (int k = 0; k < 3; ++k) out[k * plane + at] = sum[k] / static_cast<float>(count);
    }
  });
  if (ring_mean) fill_outside_photo(out, inside, crop_size, crop_size);
  if (coverage) *coverage = std::move(inside);
  return out;
}

}  // namespace facetool
