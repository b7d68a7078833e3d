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
  double cross[3] = {0, 0, 0}, square[3] = {0, 0, 0};
  bool grey = true;  // the crop's three channels equal in the mask
  for (int c = 0; c < 3; ++c) {
    const float* r = reconstruction + c * plane;
    const float* i = image + c * plane;
    for (size_t p = 0; p < plane; ++p)
      if (mask[p] > 0.5f) {
        cross[c] += static_cast<double>(r[p]) * i[p];
        square[c] += static_cast<double>(r[p]) * r[p];
        grey = grey && i[p] == image[p];
      }
  }
  if (grey) {  // one gain for the three colours: a grey photo says nothing of the light's colour
    for (int c = 1; c < 3; ++c) {
      cross[0] += cross[c];
      square[0] += square[c];
    }
    for (int c = 1; c < 3; ++c) {
      cross[c] = cross[0];
      square[c] = square[0];
    }
  }
  for (int c = 0; c < 3; ++c)
    if (square[c] > 0)
      gain[c] = static_cast<float>(std::clamp(cross[c] / square[c], double{kMinLightGain}, double{kMaxLightGain}));
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
