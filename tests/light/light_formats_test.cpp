// Light formats: round trips, and each format's own shading formula against facetool's at
// 1,000 directions (the observable a light produces: shading at a normal).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <unistd.h>

#include "libs/light/light_formats.h"
#include "core/sh/clamped_cosine.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sphere_samples.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {


sh::RgbLight random_light(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  sh::RgbLight l;
  for (double& v : l) v = dist(rng);
  for (int c = 0; c < 3; ++c) l[c * 9] = 3.0 + dist(rng);  // a positive ambient term
  return l;
}

// facetool's shading with visibility 1: (1 / pi) sum_i A_l L_i Y_i(n) (image = albedo * shading).
double facetool_shading(const sh::RgbLight& light, int channel, const sh::Vec3& n) {
  const sh::ShCoeffs y = sh::sh_basis(n);
  double s = 0;
  for (int i = 0; i < 9; ++i) s += sh::cosine_band_factor(sh::sh_band(i)) * light[channel * 9 + i] * y[i];
  return s / kPi;
}

// One folder per test and process: CTest runs these tests in parallel (and other checkouts may
// run them at the same time), and each test removes its folder at the end.
std::filesystem::path temp_dir() {
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  auto dir = std::filesystem::temp_directory_path() /
             ("facetool_light_test_" + test + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(LightFormats, SfsnetShadingMatchesFacetoolAt1000Directions) {
  const sh::RgbLight light = random_light(1);
  const auto sfs = light::to_sfsnet(light);
  for (const sh::Vec3& n : sh::fibonacci_sphere(1000)) {
    for (int c = 0; c < 3; ++c) {
      std::array<double, 9> channel;
      std::copy(sfs.begin() + 9 * c, sfs.begin() + 9 * c + 9, channel.begin());
      ASSERT_NEAR(light::sfsnet_shading(channel, n), facetool_shading(light, c, n), 1e-12);
    }
  }
  // And from SfSNet's side: arbitrary SfSNet values shade the same once imported.
  std::array<double, 27> values;
  std::mt19937 rng(2);
  for (double& v : values) v = std::uniform_real_distribution<double>(-1, 1)(rng);
  const sh::RgbLight imported = light::from_sfsnet(values);
  for (const sh::Vec3& n : sh::fibonacci_sphere(1000)) {
    std::array<double, 9> g;
    std::copy(values.begin() + 9, values.begin() + 18, g.begin());
    ASSERT_NEAR(light::sfsnet_shading(g, n), facetool_shading(imported, 1, n), 1e-12);
  }
}

TEST(LightFormats, DprShadingMatchesFacetoolInItsOwnFrame) {
  std::array<double, 9> values;
  std::mt19937 rng(3);
  for (double& v : values) v = std::uniform_real_distribution<double>(-1, 1)(rng);
  const sh::RgbLight imported = light::from_dpr(values);
  for (const sh::Vec3& n_dpr : sh::fibonacci_sphere(1000))
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(light::dpr_shading(values, n_dpr),
                  facetool_shading(imported, c, light::dpr_to_world(n_dpr)), 1e-12);
  // DPR's frame: the sphere point facing the viewer has y = -1, which is facetool's +Z.
  const sh::Vec3 towards_viewer = light::dpr_to_world({0, -1, 0});
  EXPECT_NEAR(towards_viewer[2], 1.0, 1e-15);
  EXPECT_NEAR(light::dpr_to_world({0, 0, 1})[1], 1.0, 1e-15);  // DPR's z is up
}

TEST(LightFormats, FilesRoundTripInEveryFormat) {
  const auto dir = temp_dir();
  light::LightFile file;
  file.light = random_light(4);
  file.metadata["source"] = "test";
  light::write_light((dir / "l.json").string(), file, light::Format::Facetool);
  light::LightFile back = light::read_light((dir / "l.json").string());
  for (int i = 0; i < 27; ++i) EXPECT_DOUBLE_EQ(back.light[i], file.light[i]);
  EXPECT_EQ(back.metadata.at("source"), "test");

  light::write_light((dir / "l_sfs.txt").string(), file, light::Format::Sfsnet);
  EXPECT_EQ(light::guess_format((dir / "l_sfs.txt").string()), light::Format::Sfsnet);
  back = light::read_light((dir / "l_sfs.txt").string());
  for (int i = 0; i < 27; ++i) EXPECT_NEAR(back.light[i], file.light[i], 1e-7 * std::abs(file.light[i]) + 1e-9);

  // DPR is grey: a grey light survives, a coloured one comes back as its luma.
  light::LightFile grey;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 9; ++i) grey.light[c * 9 + i] = file.light[i];
  light::write_light((dir / "l_dpr.txt").string(), grey, light::Format::Dpr);
  EXPECT_EQ(light::guess_format((dir / "l_dpr.txt").string()), light::Format::Dpr);
  back = light::read_light((dir / "l_dpr.txt").string());
  for (int i = 0; i < 27; ++i) EXPECT_NEAR(back.light[i], grey.light[i], 1e-7);
  std::filesystem::remove_all(dir);
}

TEST(LightFormats, BadFilesGiveClearErrors) {
  const auto dir = temp_dir();
  auto message = [](const std::string& path) -> std::string {
    try {
      light::read_light(path);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message((dir / "missing.txt").string()).find("missing.txt"), std::string::npos);
  std::ofstream((dir / "eight.txt").string()) << "1 2 3 4 5 6 7 8\n";
  EXPECT_NE(message((dir / "eight.txt").string()).find("8 numbers"), std::string::npos);
  std::ofstream((dir / "word.txt").string()) << "1 2 three\n";
  EXPECT_NE(message((dir / "word.txt").string()).find("three"), std::string::npos);
  std::ofstream((dir / "nan.txt").string()) << "1 2 3 4 5 6 7 8 nan\n";
  EXPECT_NE(message((dir / "nan.txt").string()).find("non-finite"), std::string::npos);
  std::ofstream((dir / "bad.json").string()) << "{\"format\": \"facetool-light\", \"version\": 1, "
                                                 "\"coefficients\": {\"r\": [1, 2]}}";
  EXPECT_NE(message((dir / "bad.json").string()).find("9 numbers"), std::string::npos);
  std::ofstream((dir / "junk.json").string()) << "{ not json";
  EXPECT_NE(message((dir / "junk.json").string()).find("not valid JSON"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace facetool
