// The head-masked Gaussian of the fitted normals, computed on the head's bounding box.
#include "libs/fit/normal_smoothing.h"

#include <algorithm>
#include <cmath>

#include "core/util/error.h"
#include "libs/image/gaussian_blur.h"

namespace facetool {

void smooth_normals(std::vector<float>& normal, const std::vector<uint8_t>& head, int width, int height,
                    double sigma_px) {
  check(width > 0 && height > 0, "smooth_normals: empty image ", width, "x", height);
  const size_t plane = static_cast<size_t>(width) * height;
  check(normal.size() == 3 * plane && head.size() == plane, "smooth_normals: ", normal.size(), " normal and ",
        head.size(), " head values for ", width, "x", height);
  check(std::isfinite(sigma_px) && sigma_px >= 0, "smooth_normals: sigma ", sigma_px, " must be finite and >= 0");
  if (sigma_px == 0) return;
  int x0 = width, y0 = height, x1 = -1, y1 = -1;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (head[static_cast<size_t>(y) * width + x]) {
        x0 = std::min(x0, x), x1 = std::max(x1, x);
        y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
  if (x1 < 0) return;
  // Only covered pixels give, and all of them lie in the head's box: blurring the box alone gives
  // the same sums. Where the kernel meets the box's edge the blur renormalises it, which cancels
  // in the ratio below (the sums and the coverage are cut alike).
  const int w = x1 - x0 + 1, h = y1 - y0 + 1;
  const size_t box = static_cast<size_t>(w) * h;
  std::vector<float> planes(4 * box, 0.0f);  // the normal times the coverage (x, y, z), the coverage
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y + y0) * width + (x + x0), b = static_cast<size_t>(y) * w + x;
      if (!head[p]) continue;
      for (int c = 0; c < 3; ++c) planes[c * box + b] = normal[c * plane + p];
      planes[3 * box + b] = 1.0f;
    }
  const std::vector<float> blurred = gaussian_blur(planes, 4, w, h, sigma_px);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y + y0) * width + (x + x0), b = static_cast<size_t>(y) * w + x;
      if (!head[p]) continue;
      const double n[3] = {blurred[b], blurred[box + b], blurred[2 * box + b]};
      const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(length > 1e-6 * blurred[3 * box + b])) continue;  // opposed normals cancel: keep the pixel's own
      for (int c = 0; c < 3; ++c) normal[c * plane + p] = static_cast<float>(n[c] / length);
    }
}

}  // namespace facetool
