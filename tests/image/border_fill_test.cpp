// The ring-mean fill outside the photo and the mask cut against plain loops over the crop.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "libs/image/border_fill.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

// Coverage of a crop whose photo ends at the column x_edge (partial pixel there) and below row 3.
std::vector<float> coverage_with_edges(int w, int h) {
  std::vector<float> c(static_cast<size_t>(w) * h, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float& v = c[static_cast<size_t>(y) * w + x];
      if (x > 11) v = 0.0f;
      else if (x == 11) v = 0.25f;
      if (y < 3) v = 0.0f;
    }
  return c;
}

TEST(BorderFill, RingMeanIsTheMeanOfInsidePixelsNearAnOutsidePixel) {
  const int w = 16, h = 12, ring = 2;
  const std::vector<float> rgb = testing::random_values(3 * w * h, 7);
  const std::vector<float> cov = coverage_with_edges(w, h);
  // Plain: for every fully inside pixel, look at every pixel within `ring` (Chebyshev).
  double sum[3] = {0, 0, 0};
  int count = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (cov[y * w + x] < 1) continue;
      bool near = false;
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
          near = near || (std::max(std::abs(i - x), std::abs(j - y)) <= ring && cov[j * w + i] < 1);
      if (!near) continue;
      for (int k = 0; k < 3; ++k) sum[k] += rgb[k * w * h + y * w + x];
      ++count;
    }
  ASSERT_GT(count, 0);
  const std::array<float, 3> got = ring_mean_colour(rgb, cov, w, h, ring);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], sum[k] / count, 1e-6) << "channel " << k;
}

TEST(BorderFill, FillBlendsByCoverageAndLeavesInsidePixelsAlone) {
  const int w = 16, h = 12;
  const std::vector<float> rgb = testing::random_values(3 * w * h, 8);
  const std::vector<float> cov = coverage_with_edges(w, h);
  std::vector<float> filled = rgb;
  const std::array<float, 3> fill = fill_outside_photo(filled, cov, w, h);
  const std::array<float, 3> expected = ring_mean_colour(rgb, cov, w, h, border_ring_width(16));
  EXPECT_EQ(border_ring_width(16), 1);
  EXPECT_EQ(border_ring_width(64), 2);
  EXPECT_EQ(border_ring_width(128), 4);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(fill[k], expected[k]);
  for (int p = 0; p < w * h; ++p)
    for (int k = 0; k < 3; ++k) {
      const float c = cov[p];
      EXPECT_NEAR(filled[k * w * h + p], c * rgb[k * w * h + p] + (1 - c) * fill[k], 1e-6) << "pixel " << p;
    }
}

TEST(BorderFill, NoRingGivesZeroAndTheMaskIsCutBelowHalfCoverage) {
  const int w = 4, h = 4;
  const std::vector<float> rgb = testing::random_values(3 * w * h, 9);
  const std::array<float, 3> none = ring_mean_colour(rgb, std::vector<float>(w * h, 1.0f), w, h, 1);
  EXPECT_EQ(none[0], 0.0f);
  std::vector<float> mask(w * h, 1.0f), cov(w * h, 1.0f);
  cov[0] = 0.0f;
  cov[1] = 0.49f;
  cov[2] = 0.5f;
  cut_mask_outside_photo(mask, cov);
  EXPECT_EQ(mask[0], 0.0f);
  EXPECT_EQ(mask[1], 0.0f);
  EXPECT_EQ(mask[2], 1.0f);
  EXPECT_EQ(mask[3], 1.0f);
}

}  // namespace
}  // namespace facetool
