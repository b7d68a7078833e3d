// Tests of equirectangular map projection, with maps written by OpenImageIO into a temp dir.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "libs/light/environment_map_file.h"
#include "core/sh/sh_basis.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool::sh {
namespace {


class EnvmapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("facetool_envmap_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, int width, int height, int channels,
                    const std::vector<float>& pixels) {
    const std::string path = (dir_ / name).string();
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out != nullptr);
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
    EXPECT_TRUE(out->open(path, spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    out->close();
    return path;
  }
  std::filesystem::path dir_;
};

TEST(EquirectMapping, CentreIsMinusZAndQuarterIsPlusX) {
  const Vec3 centre = equirect_direction(0.5, 0.5);
  EXPECT_NEAR(centre[2], -1.0, 1e-15);
  const Vec3 right = equirect_direction(0.75, 0.5);
  EXPECT_NEAR(right[0], 1.0, 1e-15);
  const Vec3 top = equirect_direction(0.3, 0.0);
  EXPECT_NEAR(top[1], 1.0, 1e-15);
  const Vec3 edge = equirect_direction(0.0, 0.5);
  EXPECT_NEAR(edge[2], 1.0, 1e-15);
}

TEST_F(EnvmapTest, ConstantMapGivesOnlyTheConstantCoefficient) {
  const int w = 64, h = 32;
  for (const char* name : {"constant.exr", "constant.hdr"}) {
    const RgbLight l =
        project_environment_map_file(write(name, w, h, 3, std::vector<float>(w * h * 3, 1.0f)));
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < kCoeffCount; ++i)
        EXPECT_NEAR(l[c * kCoeffCount + i], i == 0 ? 2.0 * std::sqrt(kPi) : 0.0, 1e-10)
            << name << " channel " << c << " coefficient " << i;
  }
}

TEST_F(EnvmapTest, SmallLitRegionGivesTheShOfADelta) {
  // A 2x2-pixel patch around (u, v) = (0.625, 0.25) of a 512x256 map, red = 1, green = 2.
  const int w = 512, h = 256;
  std::vector<float> pixels(static_cast<size_t>(w) * h * 3, 0.0f);
  double solid_angle = 0.0;
  for (int r = 63; r <= 64; ++r)
    for (int c = 319; c <= 320; ++c) {
      pixels[(static_cast<size_t>(r) * w + c) * 3 + 0] = 1.0f;
      pixels[(static_cast<size_t>(r) * w + c) * 3 + 1] = 2.0f;
      solid_angle += (2.0 * kPi / w) * (std::cos(kPi * r / h) - std::cos(kPi * (r + 1) / h));
    }
  const RgbLight l = project_environment_map_file(write("delta.exr", w, h, 3, pixels));
  const ShCoeffs y = sh_basis(equirect_direction(0.625, 0.25));
  for (int i = 0; i < kCoeffCount; ++i) {
    // Patch ~0.7 degrees wide: the basis varies by ~1e-4 relative across it.
    EXPECT_NEAR(l[i], solid_angle * y[i], 1e-3 * solid_angle) << "R coefficient " << i;
    EXPECT_NEAR(l[kCoeffCount + i], 2.0 * solid_angle * y[i], 2e-3 * solid_angle) << i;
    EXPECT_EQ(l[2 * kCoeffCount + i], 0.0);
  }
}

TEST_F(EnvmapTest, GreyMapIsUsedForAllChannels) {
  const RgbLight l = project_environment_map_file(write("grey.exr", 16, 8, 1,
                                                        std::vector<float>(16 * 8, 0.5f)));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(l[c * kCoeffCount], std::sqrt(kPi), 1e-10);
}

TEST_F(EnvmapTest, BadFilesAreErrors) {
  EXPECT_THROW(read_environment_map((dir_ / "missing.hdr").string()), Error);
  const std::string junk = (dir_ / "junk.exr").string();
  std::ofstream(junk) << "not an image";
  EXPECT_THROW(read_environment_map(junk), Error);
  EXPECT_THROW(read_environment_map(write("two.exr", 4, 2, 2, std::vector<float>(16, 1.0f))),
               Error);
  EnvironmentMap bad;
  bad.width = 4;
  bad.height = 2;
  EXPECT_THROW(project_environment_map(bad), Error);
}

}  // namespace
}  // namespace facetool::sh
