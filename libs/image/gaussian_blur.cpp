// A separable Gaussian blur with the kernel renormalised at the image's edges.
#include "gaussian_blur.h"

#include <cmath>
#include <cstdint>

#include "core/util/error.h"

namespace facetool {

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

  // One pass along an axis: the `count` samples `stride` apart from `in` to `out`.
  auto pass = [&](const float* in, float* out, int count, int64_t stride) {
    for (int i = 0; i < count; ++i) {
      double sum = 0, weight = 0;
      for (int k = -radius; k <= radius; ++k) {
        const int j = i + k;
        if (j < 0 || j >= count) continue;
        sum += kernel[k + radius] * in[j * stride];
        weight += kernel[k + radius];
      }
      out[i * stride] = static_cast<float>(sum / weight);
    }
  };
  std::vector<float> rows(image.size()), result(image.size());
  for (int c = 0; c < channels; ++c) {
    const float* src = image.data() + c * plane;
    float* mid = rows.data() + c * plane;
    float* dst = result.data() + c * plane;
    for (int y = 0; y < height; ++y) {
      const int64_t row = static_cast<int64_t>(y) * width;
      pass(src + row, mid + row, width, 1);
    }
    for (int x = 0; x < width; ++x) pass(mid + x, dst + x, height, width);
  }
  return result;
}

}  // namespace facetool
