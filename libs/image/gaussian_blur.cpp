// A separable Gaussian blur with the kernel renormalised at the image's edges.
#include "gaussian_blur.h"

#include <algorithm>
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

  // Rows: each output the kernel's weighted mean of the samples inside the row; the interior,
  // where the whole kernel fits, without the bounds checks and with the kernel's full sum.
  double kernel_sum = 0;
  for (double k : kernel) kernel_sum += k;
  auto row_pass = [&](const float* in, float* out, int count) {
    for (int i = 0; i < count; ++i) {
      double sum = 0, weight = 0;
      if (i >= radius && i + radius < count) {
        const float* window = in + i - radius;
        for (int k = 0; k <= 2 * radius; ++k) sum += kernel[k] * window[k];
        weight = kernel_sum;
      } else {
        for (int k = -radius; k <= radius; ++k) {
          const int j = i + k;
          if (j < 0 || j >= count) continue;
          sum += kernel[k + radius] * in[j];
          weight += kernel[k + radius];
        }
      }
      out[i] = static_cast<float>(sum / weight);
    }
  };
  // Columns: a whole output row at a time, from the input rows the kernel reaches (contiguous
  // loads; the same sums as one column at a time).
  std::vector<double> sums(static_cast<size_t>(width));
  auto column_pass = [&](const float* in, float* out) {
    for (int y = 0; y < height; ++y) {
      std::fill(sums.begin(), sums.end(), 0.0);
      double weight = 0;
      for (int k = -radius; k <= radius; ++k) {
        const int j = y + k;
        if (j < 0 || j >= height) continue;
        const double g = kernel[k + radius];
        const float* row = in + static_cast<int64_t>(j) * width;
        for (int x = 0; x < width; ++x) sums[x] += g * row[x];
        weight += g;
      }
      float* target = out + static_cast<int64_t>(y) * width;
      for (int x = 0; x < width; ++x) target[x] = static_cast<float>(sums[x] / weight);
    }
  };
  std::vector<float> rows(image.size()), result(image.size());
  for (int c = 0; c < channels; ++c) {
    const float* src = image.data() + c * plane;
    float* mid = rows.data() + c * plane;
    for (int y = 0; y < height; ++y) {
      const int64_t row = static_cast<int64_t>(y) * width;
      row_pass(src + row, mid + row, width);
    }
    column_pass(mid, result.data() + c * plane);
  }
  return result;
}

}  // namespace facetool
