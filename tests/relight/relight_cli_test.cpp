// `facetool relight` end to end on the example photos with random weights: a photo's own light
// (transferred from itself, turned a full turn, as orbit frame 0) returns the photo within 8-bit
// rounding; the written files; bad inputs (wrong light size, not an envmap, no face) fail cleanly.
#include <gtest/gtest.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libs/face/face_detector.h"
#include "tests/support/cli_run.h"
#include "libs/io/image_io.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

int run(const std::string& args, const std::string& log) {
  return testing::run_cli(FACETOOL_EXE, args, log);
}

using testing::read_text;

// The largest difference of two 8-bit images read as stored values in [0, 1], over pixels not in
// the top-right `skip` x `skip` corner.
double max_difference(const std::string& a_path, const std::string& b_path, int skip = 0) {
  const RgbImage a = read_rgb_image(a_path), b = read_rgb_image(b_path);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  double worst = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (x >= a.width - skip && y < skip) continue;
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(a.at(x, y)[c]) - b.at(x, y)[c]));
    }
  return worst;
}

// Random weights, a narrow network: the pipeline, not the model, is under test.
const std::string kNet = " --init random --width 16 ";
// One 8-bit step, plus the float noise of the sRGB round trip.
constexpr double kOneStep = 1.0 / 255 + 1e-6;

class RelightCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kDefaultLandmarkModel))
      GTEST_SKIP() << "dlib's landmark model " << kDefaultLandmarkModel << " is not installed (libdlib-data)";
    dir_ = fs::temp_directory_path() / ("facetool_relight_cli_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "photos");
    fs::copy_file(fs::path(FACETOOL_EXAMPLES_DIR) / "photos" / "astronaut.png", dir_ / "photos" / "astronaut.png");
    RgbImage plain;  // no face: a smooth pattern
    plain.width = 200;
    plain.height = 150;
    plain.pixels.resize(200 * 150 * 3);
    for (size_t i = 0; i < plain.pixels.size(); ++i) plain.pixels[i] = 0.3f + 0.2f * std::sin(i * 0.001f);
    write_png_atomically((dir_ / "wall.png").string(), plain);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  std::string at(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(RelightCliTest, OwnLightReturnsThePhotoAndWritesEveryFile) {
  const std::string photo = at("photos/astronaut.png");
  ASSERT_EQ(run("relight " + photo + " --light-from " + photo + kNet + "--no-visibility --orbit 3 -o " + at("out"),
                at("log")), 0) << read_text(at("log"));
  const fs::path folder = dir_ / "out" / "astronaut";
  for (const char* name : {"relit.png", "shading.png", "relit_shading.png", "light.json", "sheet.png",
                           "relit_no_visibility.png", "orbit/frame_000.png", "orbit/frame_002.png", "orbit.gif"})
    EXPECT_TRUE(fs::exists(folder / name)) << name;
  // Transfer from itself is the identity (ratio mode, the photo's own estimated light).
  EXPECT_LE(max_difference((folder / "relit.png").string(), photo), kOneStep);
  // Orbit frame 0 is the own light again (the light's sphere covers the top-right corner).
  EXPECT_LE(max_difference((folder / "orbit/frame_000.png").string(), photo, 512 / 5 + 1), kOneStep);
  // The other frames turn the light: the face changes.
  EXPECT_GT(max_difference((folder / "orbit/frame_001.png").string(), photo, 512 / 5 + 1), 4.0 / 255);
  // The GIF holds the three frames.
  auto gif = OIIO::ImageInput::open((folder / "orbit.gif").string());
  ASSERT_TRUE(gif);
  int frames = 0;
  while (gif->seek_subimage(frames, 0)) ++frames;
  EXPECT_EQ(frames, 3);
  // The light file is the photo's own, readable back by `light show`.
  EXPECT_EQ(run("light show " + (folder / "light.json").string() + " -o " + at("light.png"), at("log2")), 0);
}

TEST_F(RelightCliTest, FullTurnOfTheLightReturnsThePhoto) {
  const std::string photo = at("photos/astronaut.png");
  ASSERT_EQ(run("relight " + photo + " --light-from " + photo + " --rotate 360,0,0" + kNet + "-o " + at("turn"),
                at("log")), 0) << read_text(at("log"));
  EXPECT_LE(max_difference(at("turn/astronaut/relit.png"), photo), kOneStep);
  ASSERT_EQ(run("relight " + photo + " --light-from " + photo + " --rotate 90,0,0" + kNet + "-o " + at("quarter"),
                at("log")), 0) << read_text(at("log"));
  EXPECT_GT(max_difference(at("quarter/astronaut/relit.png"), photo), 4.0 / 255);
}

// `light from-direction` writes the light `relight --light-direction` uses: the same relit photo
// from the file as from the angles, and another direction gives another photo.
TEST_F(RelightCliTest, LightDirectionRoundTripsThroughALightFile) {
  const std::string photo = at("photos/astronaut.png");
  ASSERT_EQ(run("light from-direction 35,15 --ambient 0.2 --intensity 1.5 -o " + at("side.json"), at("log")), 0)
      << read_text(at("log"));
  ASSERT_EQ(run("relight " + photo + " --light " + at("side.json") + kNet + "-o " + at("file"), at("log")), 0)
      << read_text(at("log"));
  ASSERT_EQ(run("relight " + photo + " --light-direction 35,15 --ambient 0.2 --intensity 1.5" + kNet + "-o " +
                    at("angles"), at("log")), 0)
      << read_text(at("log"));
  EXPECT_EQ(max_difference(at("file/astronaut/relit.png"), at("angles/astronaut/relit.png")), 0.0);
  ASSERT_EQ(run("relight " + photo + " --light-direction=-35,15 --ambient 0.2 --intensity 1.5" + kNet + "-o " +
                    at("other"), at("log")), 0)
      << read_text(at("log"));
  EXPECT_GT(max_difference(at("other/astronaut/relit.png"), at("angles/astronaut/relit.png")), 4.0 / 255);
  // --ambient without --light-direction, and a malformed direction, are usage errors.
  EXPECT_EQ(run("relight " + photo + " --light " + at("side.json") + " --ambient 0.3" + kNet + "-o " + at("bad1"),
                at("log")), 2);
  EXPECT_EQ(run("relight " + photo + " --light-direction 35" + kNet + "-o " + at("bad2"), at("log")), 2);
  EXPECT_NE(read_text(at("log")).find("azimuth,elevation"), std::string::npos) << read_text(at("log"));
}

TEST_F(RelightCliTest, BadInputsFailWithClearMessagesAndWriteNothing) {
  const std::string photo = at("photos/astronaut.png");
  {  // a light file of the wrong size: 20 numbers
    std::ofstream bad(at("bad_light.txt"));
    for (int i = 0; i < 20; ++i) bad << 0.1 * i << "\n";
  }
  EXPECT_NE(run("relight " + photo + " --light " + at("bad_light.txt") + kNet + "-o " + at("out1"), at("log")), 0);
  EXPECT_NE(read_text(at("log")).find("bad_light.txt"), std::string::npos) << read_text(at("log"));
  EXPECT_FALSE(fs::exists(at("out1")));

  {  // an "envmap" that is text
    std::ofstream bad(at("env.hdr"));
    bad << "not a panorama\n";
  }
  EXPECT_NE(run("relight " + photo + " --envmap " + at("env.hdr") + kNet + "-o " + at("out2"), at("log")), 0);
  EXPECT_NE(read_text(at("log")).find("env.hdr"), std::string::npos) << read_text(at("log"));
  EXPECT_FALSE(fs::exists(at("out2")));
  // an image that is not a 2:1 panorama
  EXPECT_NE(run("relight " + photo + " --envmap " + at("wall.png") + kNet + "-o " + at("out3"), at("log")), 0);
  EXPECT_NE(read_text(at("log")).find("not an equirectangular"), std::string::npos) << read_text(at("log"));
  EXPECT_FALSE(fs::exists(at("out3")));

  // a photo without a face: reported, skipped, exit status 1, no folder for it
  EXPECT_EQ(run("relight " + at("wall.png") + " --light-from " + photo + kNet + "-o " + at("out4"), at("log")), 1);
  EXPECT_NE(read_text(at("log")).find("no face"), std::string::npos) << read_text(at("log"));
  EXPECT_FALSE(fs::exists(at("out4/wall")));
  // ... and as the light source: nothing written at all
  EXPECT_NE(run("relight " + photo + " --light-from " + at("wall.png") + kNet + "-o " + at("out5"), at("log")), 0);
  EXPECT_NE(read_text(at("log")).find("no face"), std::string::npos) << read_text(at("log"));
  EXPECT_FALSE(fs::exists(at("out5")));

  // A failed run leaves an earlier result untouched.
  ASSERT_EQ(run("relight " + photo + " --light-from " + photo + kNet + "-o " + at("keep"), at("log")), 0);
  const std::string before = read_text(at("keep/astronaut/relit.png"));
  EXPECT_NE(run("relight " + photo + " --light " + at("bad_light.txt") + kNet + "-o " + at("keep"), at("log")), 0);
  EXPECT_EQ(read_text(at("keep/astronaut/relit.png")), before);
}

}  // namespace
}  // namespace facetool
