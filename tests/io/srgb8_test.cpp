// linear_to_srgb8 (a table of precomputed steps) gives the byte of the direct computation,
// lround(255 * linear_to_srgb(v)), for every value tried: around each step, at random, and at
// the special values; unit_to_byte rounds as lround; read_rgb_image's table for 8-bit files gives the floats of the per-value
// decoding of OpenImageIO's floats.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

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

// unit_to_byte against lround(255 * v) of the clamped value, on the floats from -1.25 to 1.25
// (every 61st bit pattern: about 35 million), the halves k + 0.5 exactly and the floats beside
// them, and the special values; and the byte of linear_to_srgb8(x) / 255 (how a data layer's
// picture writes the photo where only the photo shows) is the byte of linear_to_srgb(x).
uint8_t rounded_directly(float v) {
  const float c = std::min(1.0f, std::max(0.0f, v));
  return static_cast<uint8_t>(std::lround((c == c ? c : 0.0f) * 255.0f));
}

TEST(Srgb8, UnitToByteRoundsAsLround) {
  long checked = 0;
  auto check_value = [&](float v) {
    ++checked;
    ASSERT_EQ(unit_to_byte(v), rounded_directly(v)) << v;
  };
  for (uint32_t bits = 0;; bits += 61) {  // every 61st float from 0 up, and its negative
    float v;
    std::memcpy(&v, &bits, sizeof v);
    if (v > 1.25f) break;
    check_value(v);
    check_value(-v);
  }
  for (int k = 0; k < 255; ++k) {  // the values whose 255 v is k + 0.5, and their neighbours
    const float half = (k + 0.5f) / 255.0f;
    float v = half;
    for (int i = 0; i < 8; ++i) v = std::nextafter(v, -1.0f);
    for (int i = 0; i < 17; ++i, v = std::nextafter(v, 2.0f)) check_value(v);
  }
  for (float special : {0.0f, -0.0f, 1.0f, -1.0f, 2.0f, std::numeric_limits<float>::infinity(),
                        -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(),
                        std::numeric_limits<float>::denorm_min()})
    check_value(special);
  EXPECT_GT(checked, 10000000);
  EXPECT_EQ(unit_to_byte(0.5f), 128);  // 127.5 rounds away from zero
  EXPECT_EQ(unit_to_byte(127.49f / 255.0f), 127);
  std::mt19937 random(11);
  std::uniform_real_distribution<float> wide(-0.5f, 1.5f);
  for (int i = 0; i < 1000000; ++i) {
    const float x = wide(random);
    ASSERT_EQ(unit_to_byte(static_cast<float>(linear_to_srgb8(x)) / 255.0f), unit_to_byte(linear_to_srgb(x))) << x;
  }
}

TEST(Srgb8, EightBitFilesReadThroughTheTableAsThroughThePowerFunction) {
  // Every byte value in every channel, in an RGB PNG and a grey + alpha PNG (channel 0 is
  // replicated): read_rgb_image must give, bit for bit, what OpenImageIO's floats give when each
  // is decoded by srgb_to_linear (or kept, without decoding).
  namespace OIIO = OIIO_NAMESPACE;
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("facetool_srgb8_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const int channels : {3, 2}) {
    const int width = 256, height = 3;
    std::vector<uint8_t> pixels(static_cast<size_t>(width) * height * channels);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint8_t>((i * 37 + i / 256) % 256);
    const std::string path = (dir / ("levels" + std::to_string(channels) + ".png")).string();
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, OIIO::ImageSpec(width, height, channels, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) && out->close());
    OIIO::ImageSpec config;  // colours as stored, as read_rgb_image reads them (alpha dropped)
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    ASSERT_TRUE(in);
    std::vector<float> floats(pixels.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, floats.data()));
    in->close();
    for (const bool decode : {true, false}) {
      const RgbImage image = read_rgb_image(path, decode);
      ASSERT_EQ(image.width, width);
      ASSERT_EQ(image.height, height);
      for (size_t p = 0; p < static_cast<size_t>(width) * height; ++p)
        for (int c = 0; c < 3; ++c) {
          const float f = floats[p * channels + (channels >= 3 ? c : 0)];
          const float expected = decode ? srgb_to_linear(f) : f;
          ASSERT_EQ(std::memcmp(&image.pixels[p * 3 + c], &expected, sizeof(float)), 0)
              << "channels " << channels << ", pixel " << p << ", channel " << c << ": " << image.pixels[p * 3 + c]
              << " against " << expected;
        }
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace facetool
