// OpenImageIO is loaded only when an image needs it: JPEG and PNG files leave it unloaded, an EXR
// loads it; a damaged module is refused with a message naming it, and PNG files still read.
// This program does not link OpenImageIO itself, so its mappings show what facetool loaded.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "tests/support/temp_folder_test.h"

namespace facetool {
namespace {

bool openimageio_loaded() {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line))
    if (line.find("libOpenImageIO") != std::string::npos) return true;
  return false;
}

class ImageFileModuleTest : public testing::TempFolderTest {
 protected:
  void write_examples() {
    RgbImage rgb;
    rgb.width = 5;
    rgb.height = 4;
    for (int i = 0; i < 60; ++i) rgb.pixels.push_back(static_cast<float>(i) / 60.0f);
    write_png_atomically(file("a.png"), rgb);
    LayeredImage exr(5, 4, {"B", "G", "R"});
    exr.pixels.assign(60, 0.25f);
    write_exr_atomically(file("a.exr"), exr);
  }
};

TEST_F(ImageFileModuleTest, JpegAndPngLeaveOpenImageIoUnloadedAnExrLoadsIt) {
  write_examples();
  ASSERT_FALSE(openimageio_loaded()) << "linked into the test program: the test cannot tell";
  const RgbImage jpeg = read_rgb_image(std::string(FACETOOL_EXAMPLES_DIR) + "/photos/grace_hopper_512x512.jpg");
  EXPECT_EQ(jpeg.width, 512);
  const RgbImage png = read_rgb_image(file("a.png"));
  EXPECT_EQ(png.width, 5);
  EXPECT_FALSE(openimageio_loaded());
  const LayeredImage exr = read_exr(file("a.exr"));
  EXPECT_EQ(exr.channel_count(), 3);
  EXPECT_FLOAT_EQ(exr.pixels[7], 0.25f);
  EXPECT_TRUE(openimageio_loaded());
}

// In a fresh child process (the "threadsafe" style runs this test alone in a new run of the
// program), as the module is loaded once per process and a fork would inherit it.
TEST_F(ImageFileModuleTest, DamagedModuleIsNamedAndPngStillReads) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  write_examples();
  std::filesystem::create_directories(file("modules"));
  write("modules/facetool_openimageio.so", "\x7f" "ELF but cut short");
  const std::string modules = file("modules"), exr = file("a.exr"), png = file("a.png");
  EXPECT_EXIT(
      {
        setenv("FACETOOL_BACKEND_PATH", modules.c_str(), 1);
        if (read_rgb_image(png).width != 5) std::exit(1);
        try {
          read_exr(exr);
        } catch (const Error& e) {
          std::fprintf(stderr, "%s\n", e.what());
          std::exit(3);
        }
        std::exit(0);
      },
      ::testing::ExitedWithCode(3), "a.exr.*facetool_openimageio.so");
}

}  // namespace
}  // namespace facetool
