// The albedo from the crop and its shading: per-pixel ratios to the network's albedo, bounded and faded in the dark.
#include "libs/inference/albedo_from_shading.h"

#include <algorithm>
#include <vector>

namespace facetool {

void albedo_from_shading(const float* image, const float* shading, const float* mask, size_t plane, float* albedo) {
  std::vector<float> face_shading;
  bool grey = true;
  for (size_t p = 0; p < plane; ++p)
    if (mask[p] > 0.5f) {
      face_shading.push_back((shading[p] + shading[plane + p] + shading[2 * plane + p]) / 3.0f);
      grey = grey && image[plane + p] == image[p] && image[2 * plane + p] == image[p];
    }
  if (face_shading.empty()) return;
  const size_t mid = face_shading.size() / 2;
  std::nth_element(face_shading.begin(), face_shading.begin() + mid, face_shading.end());
  const float reference = face_shading[mid];
  if (!(reference > 0.0f)) return;
  auto bounded = [](float num, float den) {
    if (!(den > 1e-6f)) return kMaxAlbedoRatio;
    return std::clamp(num / den, 1.0f / kMaxAlbedoRatio, kMaxAlbedoRatio);
  };
  for (size_t p = 0; p < plane; ++p) {
    const float s = (shading[p] + shading[plane + p] + shading[2 * plane + p]) / 3.0f;
    const float fade = std::clamp((s / reference - kDarkShading) / (kLitShading - kDarkShading), 0.0f, 1.0f);
    if (fade <= 0.0f) continue;
    float ratio[3];
    if (grey) {
      float num = 0, den = 0;
      for (int c = 0; c < 3; ++c) {
        num += image[c * plane + p];
        den += albedo[c * plane + p] * shading[c * plane + p];
      }
      ratio[0] = ratio[1] = ratio[2] = bounded(num, den);
    } else {
      for (int c = 0; c < 3; ++c) ratio[c] = bounded(image[c * plane + p], albedo[c * plane + p] * shading[c * plane + p]);
    }
    for (int c = 0; c < 3; ++c) {
      float& a = albedo[c * plane + p];
      a = std::clamp(a * (1.0f + fade * (ratio[c] - 1.0f)), 0.0f, 1.0f);
    }
  }
}

}  // namespace facetool
