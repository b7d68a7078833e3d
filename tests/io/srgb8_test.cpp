// linear_to_srgb8 (a search over precomputed steps) gives the byte of the direct computation,
// lround(255 * linear_to_srgb(v)), for every value tried: around each step, at random, and at
// the special values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "libs/io/image_io.h"

namespace facetool {
namespace {

uint8_t directly(float v) {
  const float e = linear_to_srgb(v);
  return static_cast<uint8_t>(std::lround((e == e ? e : 0.0f) * 255.0f));
}

TEST(Srgb8, SameByteAsTheDirectComputation) {
  // Around every step: the 64 floats on each side of the value where the byte changes.
  long checked = 0;
  for (int k = 1; k <= 255; ++k) {
    // The exact step is not known to the test: find the first float giving k by a plain scan
    // outward from the analytic step (the sRGB decoding of (k - 0.5) / 255).
    const double encoded = (k - 0.5) / 255.0;
    const double step = encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
    float v = static_cast<float>(step);
    for (int i = 0; i < 64; ++i) v = std::nextafter(v, -1.0f);
    for (int i = 0; i < 129; ++i, v = std::nextafter(v, 2.0f), ++checked)
      ASSERT_EQ(linear_to_srgb8(v), directly(v)) << "at " << v << " near step " << k;
  }
  std::mt19937 random(7);
  std::uniform_real_distribution<float> wide(-0.5f, 1.5f), low(0.0f, 0.01f);
  for (int i = 0; i < 1000000; ++i, checked += 2) {
    const float a = wide(random), b = low(random);
    ASSERT_EQ(linear_to_srgb8(a), directly(a)) << a;
    ASSERT_EQ(linear_to_srgb8(b), directly(b)) << b;
  }
  for (float special : {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                        std::numeric_limits<float>::denorm_min(), 1e-30f, 0.0031308f})
    EXPECT_EQ(linear_to_srgb8(special), directly(special)) << special;
  EXPECT_GT(checked, 2000000);
  EXPECT_EQ(linear_to_srgb8(1.0f), 255);
  EXPECT_EQ(linear_to_srgb8(0.5f), 188);  // 255 * (1.055 * 0.5^(1/2.4) - 0.055) = 187.52
}

}  // namespace
}  // namespace facetool
