// A separable Gaussian blur with the kernel renormalised at the image's edges.
#include "gaussian_blur.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/util/error.h"
#include "core/util/vector_clones.h"

namespace facetool {

namespace {

// sums[i] += weight * in[i] for i in [0, n): one kernel tap over a run of samples.
FACETOOL_VECTOR_CLONES
void add_tap(const float* __restrict in, float weight, int64_t n, float* __restrict sums) {
  FACETOOL_NO_ALIAS_LOOP
  for (int64_t i = 0; i < n; ++i) sums[i] += weight * in[i];
}

// out[i] = sums[i] * scale[i].
FACETOOL_VECTOR_CLONES
void scale_sums(const float* __restrict sums, const float* __restrict scale, int64_t n, float* __restrict out) {
  FACETOOL_NO_ALIAS_LOOP
  for (int64_t i = 0; i < n; ++i) out[i] = sums[i] * scale[i];
}

}  // namespace

std::vector<float> gaussian_blur(const std::vector<float>& image, int channels, int width,
                                 int height, double sigma) {
  check(width > 0 && height > 0 && channels > 0, "gaussian_blur: empty image ", width, "x",
        height, "x", channels);
  const int64_t plane = static_cast<int64_t>(width) * height;
  check(static_cast<int64_t>(image.size()) == channels * plane, "gaussian_blur: ",
        image.size(), " values for ", channels, " planes of ", width, "x", height);
  check(std::isfinite(sigma) && sigma >= 0, "gaussian_blur: sigma ", sigma,
        " must be finite and >= 0");
  if (sigma == 0) return image;
  const int radius = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> kernel(2 * radius + 1);
  for (int k = -radius; k <= radius; ++k)
    kernel[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  std::vector<float> taps(kernel.begin(), kernel.end());
  // 1 / (the kernel's weights that fall inside a line of `count` samples), per position.
  auto inverse_weights = [&](int count) {
    std::vector<float> inverse(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) {
      double weight = 0;
      for (int k = std::max(-radius, -i); k <= std::min(radius, count - 1 - i); ++k) weight += kernel[k + radius];
      inverse[i] = static_cast<float>(1.0 / weight);
    }
    return inverse;
  };
  const std::vector<float> row_scale = inverse_weights(width), column_scale = inverse_weights(height);

  // Both passes add one tap at a time over a whole run of samples (contiguous, so the loops
  // vectorise): along a row, tap k adds in[x + k] to the sum of x for every x whose x + k is
  // inside; down the columns, tap k adds row y + k to row y's sums.
  std::vector<float> rows(image.size()), result(image.size()), sums(static_cast<size_t>(width));
  for (int c = 0; c < channels; ++c) {
    const float* src = image.data() + c * plane;
    float* mid = rows.data() + c * plane;
    float* dst = result.data() + c * plane;
    for (int y = 0; y < height; ++y) {
      const float* in = src + static_cast<int64_t>(y) * width;
      std::fill(sums.begin(), sums.end(), 0.0f);
      for (int k = -radius; k <= radius; ++k) {
        const int lo = std::max(0, -k), hi = std::min(width, width - k);
        if (lo < hi) add_tap(in + lo + k, taps[k + radius], hi - lo, sums.data() + lo);
      }
      scale_sums(sums.data(), row_scale.data(), width, mid + static_cast<int64_t>(y) * width);
    }
    for (int y = 0; y < height; ++y) {
      std::fill(sums.begin(), sums.end(), 0.0f);
      for (int k = std::max(-radius, -y); k <= std::min(radius, height - 1 - y); ++k)
        add_tap(mid + static_cast<int64_t>(y + k) * width, taps[k + radius], width, sums.data());
      float* target = dst + static_cast<int64_t>(y) * width;
      for (int x = 0; x < width; ++x) target[x] = sums[x] * column_scale[y];
    }
  }
  return result;
}

}  // namespace facetool
