// `facetool infer`: runs the built executable and checks what it writes and how it fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "libs/light/light_formats.h"
#include "libs/model/safetensors.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

int run(const std::string& args) {
  const std::string command = std::string(FACETOOL_EXE) + " infer --aligned " + args + (std::getenv("FACETOOL_TEST_VERBOSE") ? "" : " 2>/dev/null");
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class InferTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("facetool_infer_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    for (const char* name : {"a.png", "b.png"}) {
      RgbImage img;
      img.width = 40;
      img.height = 30;
      img.pixels.resize(40 * 30 * 3);
      for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(i % 97) / 97.0f;
      write_png_atomically((dir_ / name).string(), img);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const char* name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(InferTest, WritesEveryComponentAndTheRawTensors) {
  const std::string out = path("out");
  ASSERT_EQ(run(path("a.png") + " " + path("b.png") + " --init random --width 8 --input-size 16 -o " +
                out + " --raw-output " + path("raw.safetensors") + " --batch 1"),
            0);
  for (const char* image : {"a", "b"})
    for (const char* file : {"input.png", "reconstruction.png", "albedo.png", "albedo.exr",
                             "shading.png", "shading.exr", "normal.png", "normal.exr",
                             "visibility.png", "visibility.exr", "light.json", "light.png"})
      EXPECT_TRUE(fs::is_regular_file(fs::path(out) / image / file)) << image << "/" << file;
  EXPECT_TRUE(fs::is_regular_file(fs::path(out) / "contact_sheet.png"));

  SafeTensors raw = SafeTensors::read_file(path("raw.safetensors"));
  EXPECT_EQ(raw.entry("albedo").shape, (std::vector<int64_t>{2, 3, 16, 16}));
  EXPECT_EQ(raw.entry("visibility").shape, (std::vector<int64_t>{2, 9, 16, 16}));
  EXPECT_EQ(raw.entry("light").shape, (std::vector<int64_t>{2, 27}));
  // The per-image files hold the same numbers as the raw dump.
  const std::vector<float> light = raw.floats("light");
  light::LightFile b = light::read_light((fs::path(out) / "b" / "light.json").string());
  for (int i = 0; i < 27; ++i) EXPECT_NEAR(b.light[i], light[27 + i], 1e-6 * (1 + std::abs(light[27 + i])));
  LayeredImage normal = read_exr((fs::path(out) / "a" / "normal.exr").string());
  const std::vector<float> raw_normal = raw.floats("normal");
  ASSERT_EQ(normal.channel_count(), 3);
  for (size_t i = 0; i < normal.pixels.size(); i += 37) EXPECT_FLOAT_EQ(normal.pixels[i], raw_normal[i]);
}

TEST_F(InferTest, MissingImageFailsBeforeWritingAnything) {
  const std::string out = path("never");
  EXPECT_NE(run(path("a.png") + " " + path("missing.png") + " --init random --width 8 "
                "--input-size 16 -o " + out),
            0);
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(InferTest, CorruptWeightsAreRefused) {
  std::ofstream(path("bad.safetensors")) << "not a safetensors file at all";
  EXPECT_NE(run(path("a.png") + " --model " + path("bad.safetensors") + " -o " + path("o2")), 0);
  EXPECT_FALSE(fs::exists(path("o2")));
  // --model and --init together: usage (without either, the shipped model: shipped_model_test.sh).
  EXPECT_EQ(run(path("a.png") + " --model " + path("bad.safetensors") + " --init random -o " + path("o3")), 2);
}

}  // namespace
}  // namespace facetool
