// encode_png8 against OpenImageIO's PNG reader (libpng): every pixel of random RGB and RGBA
// pictures of odd sizes comes back as written; a PNG of another channel count or no pixels is refused.
#include <gtest/gtest.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <random>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "libs/io/png_encoding.h"

namespace facetool {
namespace {

namespace OIIO = OIIO_NAMESPACE;

// Decodes PNG bytes with OpenImageIO (from memory) into 8-bit interleaved pixels.
std::vector<uint8_t> decode(std::vector<unsigned char> bytes, int& width, int& height, int& channels) {
  OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
  void* proxy = &reader;
  OIIO::ImageSpec config;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open("memory.png", &config);
  EXPECT_TRUE(in != nullptr) << OIIO::geterror();
  if (!in) return {};
  width = in->spec().width;
  height = in->spec().height;
  channels = in->spec().nchannels;
  EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT8);
  std::vector<uint8_t> pixels(static_cast<size_t>(width) * height * channels);
  EXPECT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, pixels.data())) << in->geterror();
  return pixels;
}

TEST(PngEncoding, RandomPicturesOfOddSizesComeBackAsWritten) {
  std::mt19937 random(5);
  std::uniform_int_distribution<int> byte(0, 255);
  int checked = 0;
  for (const int channels : {3, 4})
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {7, 3}, {1, 65}, {65, 64}, {64, 1}, {200, 150}}) {
      std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * channels);
      // Half noise, half smooth ramps (long matches for the compressor, small "up" differences).
      for (size_t i = 0; i < pixels.size(); ++i)
        pixels[i] = (i / (w * channels)) % 2 ? static_cast<uint8_t>(byte(random)) : static_cast<uint8_t>(i % 251);
      int rw = 0, rh = 0, rc = 0;
      const std::vector<uint8_t> back = decode(encode_png8("test.png", w, h, channels, pixels.data()), rw, rh, rc);
      ASSERT_EQ(rw, w);
      ASSERT_EQ(rh, h);
      ASSERT_EQ(rc, channels);
      ASSERT_EQ(back, pixels) << w << " x " << h << " x " << channels;
      ++checked;
    }
  EXPECT_EQ(checked, 12);
}

TEST(PngEncoding, SmoothPicturesAreCompressed) {
  // A smooth 512 x 512 gradient: the "up" filter makes rows nearly constant; the file must be far
  // smaller than the pixels (a store-only stream would be larger than them).
  const int w = 512, h = 512;
  std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) pixels[(static_cast<size_t>(y) * w + x) * 3 + c] = static_cast<uint8_t>((x + y + 40 * c) / 4);
  const std::vector<unsigned char> png = encode_png8("gradient.png", w, h, 3, pixels.data());
  EXPECT_LT(png.size(), pixels.size() / 20);
}

TEST(PngEncoding, OtherChannelCountsAndEmptyPicturesAreRefused) {
  const std::vector<uint8_t> pixels(64, 0);
  EXPECT_THROW(encode_png8("grey.png", 4, 4, 1, pixels.data()), Error);
  EXPECT_THROW(encode_png8("empty.png", 0, 4, 3, pixels.data()), Error);
  try {
    encode_png8("two.png", 2, 2, 2, pixels.data());
    FAIL() << "a two-channel PNG was written";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("two.png"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace facetool
