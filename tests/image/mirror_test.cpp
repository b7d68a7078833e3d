// mirror_plane against the definition, value by value, for even and odd widths and both signs.
#include <gtest/gtest.h>

#include <vector>

#include "libs/image/mirror.h"

namespace facetool {
namespace {

TEST(MirrorPlane, EachRowIsReversedAndScaled) {
  for (int width : {1, 4, 5})
    for (float sign : {1.0f, -1.0f}) {
      const int height = 3;
      std::vector<float> before(height * width), after;
      for (int k = 0; k < height * width; ++k) before[k] = 0.5f + k;
      after = before;
      mirror_plane(after.data(), height, width, sign);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          EXPECT_EQ(after[y * width + x], sign * before[y * width + (width - 1 - x)]) << width << " " << y << " " << x;
      mirror_plane(after.data(), height, width, sign);  // twice: the plane again
      EXPECT_EQ(after, before) << width;
    }
}

}  // namespace
}  // namespace facetool
