// Ring-mean fill outside the photo and the mask cut.
#include "libs/image/border_fill.h"

#include <algorithm>
#include <cmath>

#include "core/util/error.h"

namespace facetool {

int border_ring_width(int crop_size) {
  return std::max(1, static_cast<int>(std::lround(crop_size / 32.0)));
}

std::array<float, 3> ring_mean_colour(const std::vector<float>& rgb, const std::vector<float>& coverage,
                                      int w, int h, int ring) {
  const size_t plane = static_cast<size_t>(w) * h;
  check(coverage.size() == plane && rgb.size() == 3 * plane, "border fill: ", rgb.size(), " colour values and ",
        coverage.size(), " coverage values for a ", w, "x", h, " crop");
  // "Within `ring` pixels (Chebyshev) of an outside pixel": a (2 ring + 1)^2 max filter of the
  // outside indicator, as a row pass then a column pass.
  std::vector<uint8_t> outside(plane), near_rows(plane), near(plane);
  for (size_t p = 0; p < plane; ++p) outside[p] = coverage[p] < 1.0f;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t any = 0;
      for (int i = std::max(0, x - ring); i <= std::min(w - 1, x + ring) && !any; ++i)
        any = outside[static_cast<size_t>(y) * w + i];
      near_rows[static_cast<size_t>(y) * w + x] = any;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t any = 0;
      for (int j = std::max(0, y - ring); j <= std::min(h - 1, y + ring) && !any; ++j)
        any = near_rows[static_cast<size_t>(j) * w + x];
      near[static_cast<size_t>(y) * w + x] = any;
    }
  double sum[3] = {0, 0, 0};
  size_t count = 0;
  for (size_t p = 0; p < plane; ++p)
    if (!outside[p] && near[p]) {
      for (int k = 0; k < 3; ++k) sum[k] += rgb[k * plane + p];
      ++count;
    }
  if (count == 0) return {0.0f, 0.0f, 0.0f};
  return {static_cast<float>(sum[0] / count), static_cast<float>(sum[1] / count),
          static_cast<float>(sum[2] / count)};
}

std::array<float, 3> fill_outside_photo(std::vector<float>& rgb, const std::vector<float>& coverage,
                                        int w, int h) {
  const std::array<float, 3> fill = ring_mean_colour(rgb, coverage, w, h, border_ring_width(std::max(w, h)));
  const size_t plane = static_cast<size_t>(w) * h;
  for (size_t p = 0; p < plane; ++p) {
    const float c = coverage[p];
    if (c >= 1.0f) continue;
    for (int k = 0; k < 3; ++k) rgb[k * plane + p] = c * rgb[k * plane + p] + (1.0f - c) * fill[k];
  }
  return fill;
}

void cut_mask_outside_photo(std::vector<float>& mask, const std::vector<float>& coverage) {
  check(mask.size() == coverage.size(), "border fill: a mask of ", mask.size(), " pixels and a coverage of ",
        coverage.size());
  for (size_t p = 0; p < mask.size(); ++p)
    if (coverage[p] < 0.5f) mask[p] = 0.0f;
}

}  // namespace facetool
