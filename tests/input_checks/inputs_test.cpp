// Issue 10, classes 3 and 6: files are read only when regular and of a sane size, image headers
// are checked before any pixel memory, NaN/Inf pixels are refused with their position, and every
// light text layout is read as what it is (or refused), never as another layout.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "libs/light/light_formats.h"
#include "libs/synth/light_source.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/image_limits.h"
#include "tests/support/error_text.h"
#include "tests/support/temp_folder_test.h"

namespace facetool {
namespace {
namespace fs = std::filesystem;

using ReliabilityInputs = testing::TempFolderTest;
using testing::error_text;

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST_F(ReliabilityInputs, OnlyRegularFilesOfASaneSizeAreRead) {
  const std::string small = file("small.txt");
  write(small, std::string(100, 'x'));
  EXPECT_EQ(read_regular_input_file(small, 100, "test file"), std::string(100, 'x'));
  std::string message = error_text([&] { read_regular_input_file(small, 99, "test file"); });
  EXPECT_TRUE(has(message, small) && has(message, "100 bytes") && has(message, "99-byte limit"))
      << message;
  message = error_text([&] { check_regular_input_file(dir_.string(), 1000, "test file"); });
  EXPECT_TRUE(has(message, dir_.string()) && has(message, "is a folder")) << message;
  message = error_text([&] { check_regular_input_file(file("absent"), 1000, "test file"); });
  EXPECT_TRUE(has(message, "absent") && has(message, "no such file")) << message;
  if (fs::exists("/dev/zero")) {
    message = error_text([&] { read_regular_input_file("/dev/zero", 1000, "weights file"); });
    EXPECT_TRUE(has(message, "weights file '/dev/zero' is not a regular file")) << message;
  }
  // The light reader goes through the same check: a folder named like a light file.
  fs::create_directories(file("folder.txt"));
  message = error_text([&] { light::read_light(file("folder.txt")); });
  EXPECT_TRUE(has(message, "folder.txt") && has(message, "is a folder")) << message;
}

// CRC-32 of PNG chunks (ISO 3309), written out so the test needs no zlib.
uint32_t crc32(const std::string& bytes) {
  uint32_t crc = 0xffffffffu;
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xffffffffu;
}

std::string big_endian(uint32_t v) {
  return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

std::string png_chunk(const std::string& type, const std::string& data) {
  return big_endian(static_cast<uint32_t>(data.size())) + type + data +
         big_endian(crc32(type + data));
}

TEST_F(ReliabilityInputs, HugeImageHeadersAreRefusedBeforeAllocating) {
  // A valid PNG header claiming 100000 x 100000 RGB pixels (30 GB as bytes, 120 GB as floats).
  const std::string ihdr = big_endian(100000) + big_endian(100000) + std::string("\x08\x02\x00\x00\x00", 5);
  const std::string png = file("huge.png");
  write(png, std::string("\x89PNG\r\n\x1a\n", 8) + png_chunk("IHDR", ihdr) +
                 png_chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) +
                 png_chunk("IEND", ""));
  const std::string message = error_text([&] { read_rgb_image(png, true); });
  EXPECT_TRUE(has(message, png)) << message;
  EXPECT_TRUE(has(message, "100000x100000")) << message;
  // The limit itself: exactly at it passes, one row more does not, nor too many channels.
  EXPECT_NO_THROW(check_image_dimensions("x", 16384, 16384, 3));
  EXPECT_THROW(check_image_dimensions("x", 16384, 16385, 3), Error);
  EXPECT_THROW(check_image_dimensions("x", 16384, 16384, 5), Error);
  EXPECT_NO_THROW(check_image_dimensions("x", 32768, 8192, 4));
  EXPECT_THROW(check_image_dimensions("x", 32769, 1, 3), Error);
  EXPECT_THROW(check_image_dimensions("x", 1, 32769, 3), Error);
  EXPECT_THROW(check_image_dimensions("x", 16, 16, 65), Error);
  EXPECT_THROW(check_image_dimensions("x", 0, 16, 3), Error);
  EXPECT_THROW(check_image_dimensions("x", std::numeric_limits<int>::max(),
                                      std::numeric_limits<int>::max(), 1),
               Error);
}

TEST_F(ReliabilityInputs, NonFinitePixelsAreRefusedWithTheirPosition) {
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(),
                          std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()}) {
    LayeredImage image(5, 4, {"R", "G", "B"});
    for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = 0.25f;
    image.plane(1)[2 * 5 + 3] = bad;  // channel G of pixel (x 3, y 2)
    const std::string exr = file("bad.exr");
    write_exr_atomically(exr, image);
    const std::string message = error_text([&] { read_rgb_image(exr); });
    EXPECT_TRUE(has(message, exr)) << message;
    EXPECT_TRUE(has(message, "pixel (3, 2) channel 1")) << message;
  }
  // The control: the same file with a finite value reads back exactly.
  LayeredImage image(5, 4, {"R", "G", "B"});
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = 0.25f;
  write_exr_atomically(file("good.exr"), image);
  const RgbImage good = read_rgb_image(file("good.exr"));
  for (float v : good.pixels) EXPECT_EQ(v, 0.25f);
}

// A light with every coefficient different, so that any transposition or reordering shows.
sh::RgbLight distinct_light() {
  sh::RgbLight light{};
  for (size_t k = 0; k < light.size(); ++k) light[k] = 0.1 + 0.05 * std::sin(1.7 * k + 0.3);
  light[0] = 2.0;
  light[9] = 1.6;
  light[18] = 1.2;
  return light;
}

void expect_same_light(const sh::RgbLight& a, const sh::RgbLight& b, double tolerance,
                       const std::string& what) {
  for (size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], tolerance) << what << " [" << k << "]";
}

// Issue 10: `synth --lights` read SfSNet text (3 lines of 9, as `light convert --to sfsnet`
// writes it) as facetool's 9 lines of R G B. Each layout is now recognised by its shape. The
// text keeps 9 significant digits, hence 1e-7 on coefficients of size <= 2.
TEST_F(ReliabilityInputs, EveryLightTextLayoutIsReadAsWhatItIs) {
  const sh::RgbLight light = distinct_light();
  light::LightFile source;
  source.light = light;
  const std::string sfsnet = file("sfsnet.txt"), table = file("table.txt");
  light::write_light(sfsnet, source, light::Format::Sfsnet);
  light::write_light(table, source, light::Format::RgbTable);
  EXPECT_EQ(light::guess_format(sfsnet), light::Format::Sfsnet);
  EXPECT_EQ(light::guess_format(table), light::Format::RgbTable);
  expect_same_light(read_sh_light_file(sfsnet), light, 1e-7, "synth reading SfSNet text");
  expect_same_light(read_sh_light_file(table), light, 1e-7, "synth reading its own table");
  expect_same_light(light::read_light(sfsnet).light, light, 1e-7, "light reading SfSNet");
  expect_same_light(light::read_light(table).light, light, 1e-7, "light reading the table");

  // The same 27 numbers on one line, or one per line, could be either: refused, naming the file.
  std::ifstream in(table);
  std::string numbers, word;
  while (in >> word) numbers += word + " ";
  write(file("one_line.txt"), numbers + "\n");
  std::string message = error_text([&] { read_sh_light_file(file("one_line.txt")); });
  EXPECT_TRUE(has(message, "one_line.txt") && has(message, "27 numbers on 1 line ")) << message;
  // Named explicitly, the layout that belongs to the other format is still refused.
  const light::Format sfsnet_format = light::Format::Sfsnet;
  message = error_text([&] { light::read_light(table, &sfsnet_format); });
  EXPECT_TRUE(has(message, "table.txt") && has(message, "3 lines of 9")) << message;
  const light::Format table_format = light::Format::RgbTable;
  message = error_text([&] { light::read_light(sfsnet, &table_format); });
  EXPECT_TRUE(has(message, "sfsnet.txt") && has(message, "9 lines of 'R G B'")) << message;
  // Named explicitly, SfSNet's 27 numbers on one line are SfSNet.
  std::ifstream sin(sfsnet);
  std::string sfsnet_numbers;
  while (sin >> word) sfsnet_numbers += word + " ";
  write(file("sfsnet_line.txt"), sfsnet_numbers + "\n");
  expect_same_light(light::read_light(file("sfsnet_line.txt"), &sfsnet_format).light, light, 1e-7,
                    "SfSNet on one line, format named");
  // Other counts: refused with the shape found.
  write(file("short.txt"), "1 2 3\n4 5 6\n");
  message = error_text([&] { read_sh_light_file(file("short.txt")); });
  EXPECT_TRUE(has(message, "6 numbers on 2 lines")) << message;
}

// synth --lights: an environment map with a NaN or infinite texel was silently zeroed; now it is
// refused like `light from-envmap` does, naming the map and the pixel.
TEST_F(ReliabilityInputs, EnvironmentMapsWithNonFiniteTexelsAreRefused) {
  LayeredImage map(8, 4, {"R", "G", "B"});
  for (size_t i = 0; i < map.pixels.size(); ++i) map.pixels[i] = 0.5f;
  write_exr_atomically(file("good_env.exr"), map);
  EXPECT_EQ(load_light_sources({file("good_env.exr")}).size(), 1u);
  map.plane(0)[3 * 8 + 6] = std::numeric_limits<float>::quiet_NaN();  // pixel (6, 3)
  write_exr_atomically(file("bad_env.exr"), map);
  const std::string message = error_text([&] { load_light_sources({file("bad_env.exr")}); });
  EXPECT_TRUE(has(message, "bad_env.exr") && has(message, "pixel (6, 3)")) << message;
}

}  // namespace
}  // namespace facetool
