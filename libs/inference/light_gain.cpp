// The light's per-channel gain: a closed-form least-squares scale per colour, and its application.
#include "libs/inference/light_gain.h"

#include <algorithm>

namespace facetool {

std::array<float, 3> fit_light_gain(const float* reconstruction, const float* image, const float* mask,
                                    size_t plane) {
  std::array<float, 3> gain = {1.0f, 1.0f, 1.0f};
  size_t pixels = 0;
  for (size_t p = 0; p < plane; ++p) pixels += mask[p] > 0.5f;
  if (pixels < kMinLightGainPixels) return gain;
  for (int c = 0; c < 3; ++c) {
    const float* r = reconstruction + c * plane;
    const float* i = image + c * plane;
    double cross = 0, square = 0;
    for (size_t p = 0; p < plane; ++p)
      if (mask[p] > 0.5f) {
        cross += static_cast<double>(r[p]) * i[p];
        square += static_cast<double>(r[p]) * r[p];
      }
    if (square > 0)
      gain[c] = static_cast<float>(std::clamp(cross / square, double{kMinLightGain}, double{kMaxLightGain}));
  }
  return gain;
}

void apply_light_gain(const std::array<float, 3>& gain, float* light, float* shading, float* reconstruction,
                      size_t plane) {
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < 9; ++k) light[c * 9 + k] *= gain[c];
    for (size_t p = 0; p < plane; ++p) {
      shading[c * plane + p] *= gain[c];
      reconstruction[c * plane + p] *= gain[c];
    }
  }
}

}  // namespace facetool
