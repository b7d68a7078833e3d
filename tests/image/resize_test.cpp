// resize_planar: exact block averages when shrinking by whole factors, bilinear when enlarging.
#include <gtest/gtest.h>

#include "libs/image/resize.h"
#include "core/util/error.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

TEST(Resize, ShrinkingByWholeFactorsAveragesBlocks) {
  const int w = 6, h = 4;
  std::vector<float> src = testing::random_values(2 * w * h, 1);
  std::vector<float> out = resize_planar(src, 2, w, h, 3, 2);
  ASSERT_EQ(out.size(), 2u * 3 * 2);
  for (int c = 0; c < 2; ++c)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x) {
        double sum = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) sum += src[(c * h + 2 * y + dy) * w + 2 * x + dx];
        EXPECT_NEAR(out[(c * 2 + y) * 3 + x], sum / 4, 1e-6);
      }
}

TEST(Resize, ShrinkingByFractionalFactorsKeepsTheMean) {
  std::vector<float> src = testing::random_values(7 * 5, 2);
  std::vector<float> out = resize_planar(src, 1, 7, 5, 3, 2);
  double mean_in = 0, mean_out = 0;
  for (float v : src) mean_in += v / src.size();
  for (float v : out) mean_out += v / out.size();
  EXPECT_NEAR(mean_in, mean_out, 1e-6);  // area weights sum to one over each output pixel
}

TEST(Resize, EnlargingIsBilinearWithHalfPixelCentres) {
  // 2x1 -> 4x1: positions (o + 0.5) / 2 - 0.5 = -0.25 (clamped to 0), 0.25, 0.75, 1.25 (-> 1).
  std::vector<float> out = resize_planar({1.0f, 3.0f}, 1, 2, 1, 4, 1);
  EXPECT_NEAR(out[0], 1.0f, 1e-6);
  EXPECT_NEAR(out[1], 1.5f, 1e-6);
  EXPECT_NEAR(out[2], 2.5f, 1e-6);
  EXPECT_NEAR(out[3], 3.0f, 1e-6);
}

TEST(Resize, SameSizeCopiesAndBadSizesFail) {
  std::vector<float> src = testing::random_values(3 * 4 * 4, 3);
  EXPECT_EQ(resize_planar(src, 3, 4, 4, 4, 4), src);
  EXPECT_THROW(resize_planar(src, 3, 4, 4, 0, 4), Error);
  EXPECT_THROW(resize_planar(src, 2, 4, 4, 2, 2), Error);
}

}  // namespace
}  // namespace facetool
