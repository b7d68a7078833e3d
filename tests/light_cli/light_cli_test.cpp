// Runs the built `facetool light` and `facetool render` on files written here and checks results.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "core/backend/registry.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "libs/light/light_formats.h"
#include "core/sh/light_clamp.h"
#include "core/sh/sh_basis.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {

namespace fs = std::filesystem;

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// Runs the facetool under test with `arguments` (already shell-quoted where needed). Only the
// plugins beside the executable are used.
CommandResult facetool(const std::string& arguments) {
  const std::string command =
      "FACETOOL_PLUGIN_PATH= '" FACETOOL_EXECUTABLE "' " + arguments + " 2>&1";
  CommandResult result;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  size_t got = 0;
  while ((got = fread(buffer, 1, sizeof(buffer), pipe)) > 0) result.output.append(buffer, got);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

// A fresh folder per test, removed afterwards.
class LightCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("facetool_light_cli_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path file(const std::string& name) const { return dir_ / name; }

  fs::path dir_;
};

// Writes planar float channels as an EXR.
void write_exr(const fs::path& path, int width, int height, const std::vector<std::string>& names,
               const std::vector<float>& planes) {
  LayeredImage image(width, height, names);
  image.pixels = planes;
  write_exr_atomically(path.string(), image);
}

// Writes interleaved bytes as an 8-bit PNG with `channels` channels, values as given.
void write_png_bytes(const fs::path& path, int width, int height, int channels,
                     const std::vector<unsigned char>& bytes) {
  auto out = OIIO::ImageOutput::create("png");
  ASSERT_TRUE(out);
  OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, bytes.data()));
  ASSERT_TRUE(out->close());
}

// The 9 SH basis functions written from docs/conventions.md's table (independent of core/sh).
std::array<double, 9> basis(double x, double y, double z) {
  const double k1 = std::sqrt(3 / (4 * kPi)), k2 = std::sqrt(15 / kPi) / 2;
  return {0.5 / std::sqrt(kPi),
          k1 * y,
          k1 * z,
          k1 * x,
          k2 * x * y,
          k2 * y * z,
          std::sqrt(5 / kPi) / 4 * (3 * z * z - 1),
          k2 * x * z,
          std::sqrt(15 / kPi) / 4 * (x * x - y * y)};
}

// Unoccluded shading (1/pi) sum_i A_l L_i Y_i(n) of channel c, n normalised here.
double closed_form_shading(const sh::RgbLight& light, int c, double x, double y, double z) {
  const double length = std::sqrt(x * x + y * y + z * z);
  const auto Y = basis(x / length, y / length, z / length);
  const double A[9] = {kPi,     2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4,
                       kPi / 4, kPi / 4,     kPi / 4,     kPi / 4};
  double sum = 0;
  for (int i = 0; i < 9; ++i) sum += A[i] * light[c * 9 + i] * Y[i];
  return sum / kPi;
}

sh::RgbLight test_light() {
  return {2.5, 0.3,  1.2, -0.4, 0.1,   -0.2, 0.25, 0.05, -0.1,   // R
          2.0, 0.2,  1.0, -0.2, 0.0,   -0.1, 0.2,  0.1,  0.0,    // G
          1.5, -0.1, 0.8, 0.3,  -0.05, 0.1,  0.15, 0.0,  0.05};  // B
}

void write_test_light(const fs::path& path, const sh::RgbLight& light) {
  light::LightFile file;
  file.light = light;
  light::write_light(path.string(), file, light::Format::Facetool);
}

// Direction of the linear band (L_3, L_1, L_2) = (x, y, z) of the light's red channel.
std::array<double, 3> linear_direction(const sh::RgbLight& light) {
  std::array<double, 3> d{light[3], light[1], light[2]};
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (double& v : d) v /= length;
  return d;
}

// ---------------------------------------------------------------- light from-envmap

TEST_F(LightCliTest, ConstantMapGivesTwoSqrtPiTimesItsValue) {
  const int w = 64, h = 32;
  const float value[3] = {1.0f, 0.5f, 0.25f};
  std::vector<float> planes(3 * w * h);
  for (int c = 0; c < 3; ++c)
    std::fill(planes.begin() + c * w * h, planes.begin() + (c + 1) * w * h, value[c]);
  write_exr(file("constant.exr"), w, h, {"R", "G", "B"}, planes);
  const CommandResult r = facetool("light from-envmap " + quoted(file("constant.exr")) + " -o " +
                                   quoted(file("light.json")));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const light::LightFile light = light::read_light(file("light.json").string());
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(light.light[c * 9], 2 * std::sqrt(kPi) * value[c], 1e-5) << "channel " << c;
    for (int i = 1; i < 9; ++i) EXPECT_NEAR(light.light[c * 9 + i], 0.0, 1e-5) << c << ", " << i;
  }
  EXPECT_EQ(light.metadata.at("source"), file("constant.exr").string());
  EXPECT_NE(light.metadata.at("rotation").find("yaw 0, pitch 0, roll 0"), std::string::npos);
  EXPECT_EQ(light.metadata.at("clamped"), "false");
}

// A black map with a small bright patch at panorama coordinates (u, v).
void write_patch_map(const fs::path& path, double u, double v) {
  const int w = 128, h = 64;
  std::vector<float> planes(3 * w * h, 0.0f);
  const int cx = static_cast<int>(u * w), cy = static_cast<int>(v * h);
  for (int c = 0; c < 3; ++c)
    for (int y = cy - 1; y <= cy; ++y)
      for (int x = cx - 1; x <= cx; ++x) planes[c * w * h + y * w + ((x + w) % w)] = 100.0f;
  write_exr(path, w, h, {"R", "G", "B"}, planes);
}

std::array<double, 3> rotated_direction(const fs::path& map, const std::string& rotate) {
  const fs::path out = map.string() + ".json";
  const CommandResult r =
      facetool("light from-envmap " + quoted(map) + " " + rotate + " -o " + quoted(out));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return linear_direction(light::read_light(out.string()).light);
}

void expect_direction(const std::array<double, 3>& d, double x, double y, double z,
                      const std::string& what) {
  EXPECT_GT(d[0] * x + d[1] * y + d[2] * z, 0.999)
      << what << ": got (" << d[0] << ", " << d[1] << ", " << d[2] << "), expected (" << x << ", "
      << y << ", " << z << ")";
}

TEST_F(LightCliTest, RotationFollowsTheDocumentedOrderAndSign) {
  // Patch at the panorama centre = -Z; at u = 3/4 = +X (docs/conventions.md).
  const fs::path ahead = file("ahead.exr"), right = file("right.exr");
  write_patch_map(ahead, 0.5, 0.5);
  write_patch_map(right, 0.75, 0.5);
  expect_direction(rotated_direction(ahead, ""), 0, 0, -1, "no rotation");
  expect_direction(rotated_direction(right, ""), 1, 0, 0, "no rotation, +X patch");
  // R = Ry(yaw) Rx(pitch) Rz(roll), right-hand rule.
  expect_direction(rotated_direction(ahead, "--rotate 90,0,0"), -1, 0, 0, "yaw 90");
  expect_direction(rotated_direction(ahead, "--rotate=-90,0,0"), 1, 0, 0, "yaw -90");
  expect_direction(rotated_direction(ahead, "--rotate 0,90,0"), 0, 1, 0, "pitch 90");
  expect_direction(rotated_direction(right, "--rotate 0,0,90"), 0, 1, 0, "roll 90");
  // Order: pitch after yaw would give -X here; yaw after pitch gives +Y.
  expect_direction(rotated_direction(ahead, "--rotate 90,90,0"), 0, 1, 0, "yaw+pitch");
  // Roll first: +X -> +Y, then pitch 90: +Y -> +Z.
  expect_direction(rotated_direction(right, "--rotate 0,90,90"), 0, 0, 1, "pitch+roll");
}

TEST_F(LightCliTest, ClampRaisesTheMinimumRadiance) {
  write_patch_map(file("patch.exr"), 0.3, 0.4);
  const std::string map = quoted(file("patch.exr"));
  ASSERT_EQ(facetool("light from-envmap " + map + " -o " + quoted(file("raw.json"))).exit_code, 0);
  const CommandResult r =
      facetool("light from-envmap " + map + " --clamp -o " + quoted(file("clamped.json")));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const light::LightFile raw = light::read_light(file("raw.json").string());
  const light::LightFile clamped = light::read_light(file("clamped.json").string());
  EXPECT_EQ(clamped.metadata.at("clamped"), "true");
  const double before = sh::min_radiance(sh::light_channel(raw.light, 0));
  const double after = sh::min_radiance(sh::light_channel(clamped.light, 0));
  ASSERT_LT(before, -0.05);  // a small patch rings below zero
  EXPECT_GT(after, 0.5 * before);
}

TEST_F(LightCliTest, FromEnvmapRejectsMissingMapsAndBadRotations) {
  const fs::path out = file("light.json");
  CommandResult r =
      facetool("light from-envmap " + quoted(file("absent.hdr")) + " -o " + quoted(out));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("absent.hdr"), std::string::npos) << r.output;
  write_patch_map(file("map.exr"), 0.5, 0.5);
  r = facetool("light from-envmap " + quoted(file("map.exr")) + " --rotate 1,2 -o " + quoted(out));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--rotate expects yaw,pitch,roll"), std::string::npos) << r.output;
  std::ofstream(file("broken.exr")) << "not an image";
  r = facetool("light from-envmap " + quoted(file("broken.exr")) + " -o " + quoted(out));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("broken.exr"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

// ---------------------------------------------------------------- light convert

TEST_F(LightCliTest, ConvertFacetoolSfsnetFacetoolRoundTrip) {
  write_test_light(file("light.json"), test_light());
  CommandResult r = facetool("light convert " + quoted(file("light.json")) + " " +
                             quoted(file("light.txt")) + " --to sfsnet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream text(file("light.txt"));
  std::vector<double> numbers;
  for (double v; text >> v;) numbers.push_back(v);
  EXPECT_EQ(numbers.size(), 27u);
  r = facetool("light convert " + quoted(file("light.txt")) + " " + quoted(file("back.json")) +
               " --to facetool");  // input format guessed from its 27 numbers
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const light::LightFile back = light::read_light(file("back.json").string());
  for (int k = 0; k < 27; ++k) EXPECT_NEAR(back.light[k], test_light()[k], 1e-6) << k;
  EXPECT_EQ(back.metadata.at("source_format"), "sfsnet");
}

TEST_F(LightCliTest, ConvertGreyLightThroughDpr) {
  sh::RgbLight grey{};
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 9; ++i) grey[c * 9 + i] = test_light()[i];
  write_test_light(file("grey.json"), grey);
  ASSERT_EQ(facetool("light convert " + quoted(file("grey.json")) + " " + quoted(file("dpr.txt")) +
                     " --to dpr")
                .exit_code,
            0);
  const CommandResult r = facetool("light convert " + quoted(file("dpr.txt")) + " " +
                                   quoted(file("back.json")) + " --from dpr --to facetool");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const light::LightFile back = light::read_light(file("back.json").string());
  for (int k = 0; k < 27; ++k) EXPECT_NEAR(back.light[k], grey[k], 1e-6) << k;
}

TEST_F(LightCliTest, ConvertRejectsBadFormatsAndFiles) {
  write_test_light(file("light.json"), test_light());
  CommandResult r = facetool("light convert " + quoted(file("light.json")) + " " +
                             quoted(file("x.txt")) + " --to nonsense");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown light format 'nonsense'"), std::string::npos) << r.output;
  std::ofstream(file("five.txt")) << "1 2 3 4 5\n";
  r = facetool("light convert " + quoted(file("five.txt")) + " " + quoted(file("x.json")) +
               " --to facetool");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("five.txt"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(file("x.json")));
}

// ---------------------------------------------------------------- light show

// Every writing command takes -o / --output, with --out as the older alias (issue #10, class 8);
// giving two of them is a usage error (exit 2) that writes nothing.
TEST_F(LightCliTest, OutputOptionSpellingsAgree) {
  write_test_light(file("light.json"), test_light());
  const std::string in = quoted(file("light.json"));
  for (const std::string spelling : {"-o", "--output", "--out"}) {
    const std::string name = "show" + spelling + ".png";
    const CommandResult r = facetool("light show " + in + " " + spelling + " " +
                                     quoted(file(name)) + " --size 16");
    ASSERT_EQ(r.exit_code, 0) << spelling << ": " << r.output;
    EXPECT_EQ(read_rgb_image(file(name).string()).width, 48) << spelling;
    const std::string text = "convert" + spelling + ".txt";
    const CommandResult c = facetool("light convert " + in + " " + spelling + " " +
                                     quoted(file(text)) + " --to sfsnet");
    ASSERT_EQ(c.exit_code, 0) << spelling << ": " << c.output;
    EXPECT_TRUE(fs::exists(file(text))) << spelling;
  }
  const CommandResult both = facetool("light show " + in + " -o " + quoted(file("a.png")) +
                                      " --out " + quoted(file("b.png")));
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("only once"), std::string::npos) << both.output;
  EXPECT_FALSE(fs::exists(file("a.png")));
  EXPECT_FALSE(fs::exists(file("b.png")));
  for (const std::string command : {"synth", "infer", "render"}) {
    const CommandResult help = facetool(command + " --help");
    EXPECT_NE(help.output.find("-o [ --output ]"), std::string::npos) << command << help.output;
  }
}

TEST_F(LightCliTest, ShowWritesASphereAndPanoramaOfTheExpectedSize) {
  // A light from the camera's side (+Z): brightest at the sphere's centre and the panorama's
  // left/right edges, darkest at the panorama's centre (-Z).
  sh::RgbLight front{};
  for (int c = 0; c < 3; ++c) {
    front[c * 9 + 0] = 2.0;
    front[c * 9 + 2] = 1.5;
  }
  write_test_light(file("front.json"), front);
  const CommandResult r = facetool("light show " + quoted(file("front.json")) + " -o " +
                                   quoted(file("front.png")) + " --size 40");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const RgbImage image = read_rgb_image(file("front.png").string());
  ASSERT_EQ(image.width, 120);
  ASSERT_EQ(image.height, 40);
  auto grey = [&](int x, int y) { return image.at(x, y)[0]; };
  EXPECT_GT(grey(20, 20), 0.97f);                  // sphere centre: the maximum
  EXPECT_LT(grey(0, 0), 0.2f);                     // background corner
  EXPECT_GT(grey(20, 20), grey(20, 3));            // brighter than near the rim
  EXPECT_GT(grey(40 + 1, 21), grey(40 + 41, 21));  // panorama: edge (+Z) above centre (-Z)
  EXPECT_GT(grey(40 + 78, 21), grey(40 + 41, 21));
}

TEST_F(LightCliTest, ShowRejectsANonPngOutput) {
  write_test_light(file("light.json"), test_light());
  const CommandResult r =
      facetool("light show " + quoted(file("light.json")) + " -o " + quoted(file("light.jpg")));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("light.jpg"), std::string::npos) << r.output;
}

// ---------------------------------------------------------------- render

struct Scene {
  int w = 7, h = 5;
  std::vector<float> albedo, normal;  // planar
};

// Varied unit normals (including the flat (0, 0, 1) at pixel 0) and albedo 0.5.
Scene test_scene() {
  Scene s;
  const int n = s.w * s.h;
  s.albedo.assign(3 * n, 0.5f);
  s.normal.resize(3 * n);
  for (int p = 0; p < n; ++p) {
    double x = p == 0 ? 0.0 : std::sin(0.7 * p), y = p == 0 ? 0.0 : std::cos(1.3 * p) * 0.8;
    double z = p == 0 ? 1.0 : 0.3 + 0.5 * std::cos(0.4 * p);
    const double length = std::sqrt(x * x + y * y + z * z);
    s.normal[p] = static_cast<float>(x / length);
    s.normal[n + p] = static_cast<float>(y / length);
    s.normal[2 * n + p] = static_cast<float>(z / length);
  }
  return s;
}

std::vector<float> read_planes(const fs::path& path, int expected_channels) {
  const LayeredImage image = read_exr(path.string());
  EXPECT_EQ(image.channel_count(), expected_channels);
  return image.pixels;
}

// The whole sphere open (v_0 = 2 sqrt(pi), others 0): the visibility under which the shading is
// the closed-form irradiance E(n) / pi.
void write_full_sphere_visibility(const fs::path& path, int w, int h) {
  std::vector<std::string> names;
  for (int j = 0; j < 9; ++j) names.push_back("visibility." + std::to_string(j));
  std::vector<float> visibility(9 * static_cast<size_t>(w) * h, 0.0f);
  std::fill(visibility.begin(), visibility.begin() + w * h, static_cast<float>(2 * std::sqrt(kPi)));
  write_exr(path, w, h, names, visibility);
}

TEST_F(LightCliTest, RenderMatchesTheClosedFormOnFlatAndVariedNormals) {
  const Scene s = test_scene();
  write_exr(file("albedo.exr"), s.w, s.h, {"R", "G", "B"}, s.albedo);
  write_exr(file("normal.exr"), s.w, s.h, {"X", "Y", "Z"}, s.normal);
  write_test_light(file("light.json"), test_light());
  write_full_sphere_visibility(file("full.exr"), s.w, s.h);
  const CommandResult r = facetool("render --albedo " + quoted(file("albedo.exr")) + " --normal " +
                                   quoted(file("normal.exr")) + " --visibility " +
                                   quoted(file("full.exr")) + " --light " +
                                   quoted(file("light.json")) + " -o " + quoted(file("out.exr")));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<float> image = read_planes(file("out.exr"), 3);
  const std::vector<float> shading = read_planes(file("out_shading.exr"), 3);
  const int n = s.w * s.h;
  for (int c = 0; c < 3; ++c)
    for (int p = 0; p < n; ++p) {
      const double expected =
          closed_form_shading(test_light(), c, s.normal[p], s.normal[n + p], s.normal[2 * n + p]);
      EXPECT_NEAR(shading[c * n + p], expected, 1e-5 * (1 + std::abs(expected))) << c << ", " << p;
      EXPECT_NEAR(image[c * n + p], 0.5 * expected, 1e-5 * (1 + std::abs(expected)))
          << c << ", " << p;
    }
  // The flat normal in closed form: Y_0 = 1/(2 sqrt(pi)), Y_2 = sqrt(3/(4pi)), Y_6 = sqrt(5/pi)/2.
  const sh::RgbLight L = test_light();
  const double flat =
      0.5 / kPi *
      (kPi * L[0] / (2 * std::sqrt(kPi)) + 2 * kPi / 3 * L[2] * std::sqrt(3 / (4 * kPi)) +
       kPi / 4 * L[6] * std::sqrt(5 / kPi) / 2);
  EXPECT_NEAR(image[0], flat, 1e-5);
}

// Without --visibility, render uses synth's default: the open hemisphere above the surface. The
// reference projects the hemisphere indicator [w . n > 0] on the SH basis by quadrature (a
// 400 x 800 midpoint grid in theta, phi; error ~1e-4), independent of render's closed form.
TEST_F(LightCliTest, RenderWithoutVisibilityUsesTheOpenHemisphere) {
  const Scene s = test_scene();
  const int n = s.w * s.h;
  write_exr(file("albedo.exr"), s.w, s.h, {"R", "G", "B"}, s.albedo);
  write_exr(file("normal.exr"), s.w, s.h, {"X", "Y", "Z"}, s.normal);
  write_test_light(file("light.json"), test_light());
  std::vector<std::string> names;
  for (int j = 0; j < 9; ++j) names.push_back("visibility." + std::to_string(j));
  std::vector<float> hemisphere(9 * n, 0.0f);
  const int rows = 400, columns = 800;
  for (int t = 0; t < rows; ++t)
    for (int f = 0; f < columns; ++f) {
      const double theta = kPi * (t + 0.5) / rows, phi = 2 * kPi * (f + 0.5) / columns;
      const double d[3] = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                           std::cos(theta)};
      const double weight = std::sin(theta) * (kPi / rows) * (2 * kPi / columns);
      const sh::ShCoeffs y = sh::sh_basis({d[0], d[1], d[2]});
      for (int p = 0; p < n; ++p)
        if (d[0] * s.normal[p] + d[1] * s.normal[n + p] + d[2] * s.normal[2 * n + p] > 0)
          for (int j = 0; j < 9; ++j) hemisphere[j * n + p] += static_cast<float>(weight * y[j]);
    }
  for (int p = 0; p < n; ++p) EXPECT_NEAR(hemisphere[p], std::sqrt(kPi), 1e-3);
  write_exr(file("hemisphere.exr"), s.w, s.h, names, hemisphere);
  write_full_sphere_visibility(file("full.exr"), s.w, s.h);
  const std::string inputs = "render --albedo " + quoted(file("albedo.exr")) + " --normal " +
                             quoted(file("normal.exr")) + " --light " + quoted(file("light.json"));
  ASSERT_EQ(facetool(inputs + " -o " + quoted(file("default.exr"))).exit_code, 0);
  ASSERT_EQ(facetool(inputs + " --visibility " + quoted(file("hemisphere.exr")) + " -o " +
                     quoted(file("hemisphere_out.exr"))).exit_code, 0);
  ASSERT_EQ(facetool(inputs + " --visibility " + quoted(file("full.exr")) + " -o " +
                     quoted(file("full_out.exr"))).exit_code, 0);
  const std::vector<float> by_default = read_planes(file("default.exr"), 3);
  const std::vector<float> reference = read_planes(file("hemisphere_out.exr"), 3);
  const std::vector<float> full = read_planes(file("full_out.exr"), 3);
  double largest_difference_to_full = 0;
  for (size_t k = 0; k < by_default.size(); ++k) {
    EXPECT_NEAR(by_default[k], reference[k], 2e-3 * (1 + std::abs(reference[k]))) << k;
    largest_difference_to_full =
        std::max(largest_difference_to_full, std::abs(double(by_default[k]) - full[k]));
  }
  EXPECT_GT(largest_difference_to_full, 0.01) << "the default must not be the whole sphere";
}

TEST_F(LightCliTest, RenderUsesVisibilityAndMask) {
  const Scene s = test_scene();
  const int n = s.w * s.h;
  write_exr(file("albedo.exr"), s.w, s.h, {"R", "G", "B"}, s.albedo);
  write_exr(file("normal.exr"), s.w, s.h, {"X", "Y", "Z"}, s.normal);
  // Half the unoccluded visibility: v_0 = sqrt(pi), so every value halves (the renderer is
  // linear in v).
  std::vector<std::string> names;
  for (int j = 0; j < 9; ++j) names.push_back("v" + std::to_string(j));
  std::vector<float> visibility(9 * n, 0.0f);
  std::fill(visibility.begin(), visibility.begin() + n, static_cast<float>(std::sqrt(kPi)));
  write_exr(file("visibility.exr"), s.w, s.h, names, visibility);
  std::vector<float> mask(n);
  for (int p = 0; p < n; ++p) mask[p] = p % 3 == 0 ? 0.0f : 1.0f;
  write_exr(file("mask.exr"), s.w, s.h, {"Y"}, mask);
  write_test_light(file("light.json"), test_light());
  const CommandResult r = facetool(
      "render --albedo " + quoted(file("albedo.exr")) + " --normal " + quoted(file("normal.exr")) +
      " --visibility " + quoted(file("visibility.exr")) + " --mask " + quoted(file("mask.exr")) +
      " --light " + quoted(file("light.json")) + " -o " + quoted(file("out.exr")));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<float> image = read_planes(file("out.exr"), 3);
  for (int c = 0; c < 3; ++c)
    for (int p = 0; p < n; ++p) {
      const double expected = mask[p] > 0.5f
                                  ? 0.25 * closed_form_shading(test_light(), c, s.normal[p],
                                                               s.normal[n + p], s.normal[2 * n + p])
                                  : 0.0;
      EXPECT_NEAR(image[c * n + p], expected, 1e-5 * (1 + std::abs(expected))) << c << ", " << p;
    }
}

TEST_F(LightCliTest, RenderReadsSynthStyleMultiLayerExr) {
  const Scene s = test_scene();
  const int n = s.w * s.h;
  std::vector<std::string> names = {"R",        "G",    "B",        "albedo.R", "albedo.G",
                                    "albedo.B", "mask", "normal.X", "normal.Y", "normal.Z"};
  std::vector<float> planes(3 * n, 9.0f);  // R, G, B: must not be taken for the albedo
  planes.insert(planes.end(), s.albedo.begin(), s.albedo.end());
  planes.insert(planes.end(), n, 1.0f);
  planes.insert(planes.end(), s.normal.begin(), s.normal.end());
  for (int j = 0; j < 9; ++j) {
    names.push_back("visibility." + std::to_string(j));
    planes.insert(planes.end(), n, j == 0 ? static_cast<float>(2 * std::sqrt(kPi)) : 0.0f);
  }
  write_exr(file("sample.exr"), s.w, s.h, names, planes);
  write_test_light(file("light.json"), test_light());
  const std::string sample = quoted(file("sample.exr"));
  const CommandResult r = facetool("render --albedo " + sample + " --normal " + sample +
                                   " --visibility " + sample + " --mask " + sample + " --light " +
                                   quoted(file("light.json")) + " -o " + quoted(file("out.exr")));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<float> image = read_planes(file("out.exr"), 3);
  for (int p = 0; p < n; ++p) {
    const double expected = 0.5 * closed_form_shading(test_light(), 1, s.normal[p], s.normal[n + p],
                                                      s.normal[2 * n + p]);
    EXPECT_NEAR(image[n + p], expected, 1e-5 * (1 + std::abs(expected))) << p;
  }
}

TEST_F(LightCliTest, RenderDecodesPngNormalsAndAlbedoAndWritesPng) {
  const int w = 4, h = 3, n = w * h;
  std::vector<unsigned char> normal_bytes(3 * n), albedo_bytes(3 * n);
  for (int p = 0; p < n; ++p) {
    const unsigned char encoded[3] = {static_cast<unsigned char>(100 + 10 * p),
                                      static_cast<unsigned char>(200 - 5 * p), 230};
    for (int c = 0; c < 3; ++c) {
      normal_bytes[p * 3 + c] = encoded[c];
      albedo_bytes[p * 3 + c] = static_cast<unsigned char>(150 + 20 * c);
    }
  }
  write_png_bytes(file("normal.png"), w, h, 3, normal_bytes);
  write_png_bytes(file("albedo.png"), w, h, 3, albedo_bytes);
  write_test_light(file("light.json"), test_light());
  write_full_sphere_visibility(file("full.exr"), w, h);
  const CommandResult r = facetool("render --albedo " + quoted(file("albedo.png")) + " --normal " +
                                   quoted(file("normal.png")) + " --visibility " +
                                   quoted(file("full.exr")) + " --light " +
                                   quoted(file("light.json")) + " -o " + quoted(file("out.png")));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(file("out_shading.png")));
  const RgbImage image = read_rgb_image(file("out.png").string());  // sRGB-encoded, in [0, 1]
  ASSERT_EQ(image.width, w);
  ASSERT_EQ(image.height, h);
  auto srgb_decode = [](double e) {
    return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
  };
  auto srgb_encode = [](double l) {
    l = std::min(1.0, std::max(0.0, l));
    return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
  };
  for (int p = 0; p < n; ++p)
    for (int c = 0; c < 3; ++c) {
      const double nx = 2 * normal_bytes[p * 3] / 255.0 - 1,
                   ny = 2 * normal_bytes[p * 3 + 1] / 255.0 - 1,
                   nz = 2 * normal_bytes[p * 3 + 2] / 255.0 - 1;
      const double albedo = srgb_decode(albedo_bytes[p * 3 + c] / 255.0);
      const double expected =
          srgb_encode(albedo * closed_form_shading(test_light(), c, nx, ny, nz));
      EXPECT_NEAR(image.at(p % w, p / w)[c], expected, 0.6 / 255) << p << ", " << c;
    }
}

TEST_F(LightCliTest, RenderAgreesOnEveryAvailableBackend) {
  const Scene s = test_scene();
  write_exr(file("albedo.exr"), s.w, s.h, {"R", "G", "B"}, s.albedo);
  write_exr(file("normal.exr"), s.w, s.h, {"X", "Y", "Z"}, s.normal);
  write_test_light(file("light.json"), test_light());
  const std::string inputs = " --albedo " + quoted(file("albedo.exr")) + " --normal " +
                             quoted(file("normal.exr")) + " --light " + quoted(file("light.json"));
  ASSERT_EQ(facetool("render" + inputs + " -o " + quoted(file("cpu.exr"))).exit_code, 0);
  const std::vector<float> reference = read_planes(file("cpu.exr"), 3);
  for (const std::string& backend : available_backends()) {
    if (backend == "cpu") continue;
    const fs::path out = file(backend + ".exr");
    const CommandResult r =
        facetool("--backend " + backend + " render" + inputs + " -o " + quoted(out));
    ASSERT_EQ(r.exit_code, 0) << backend << ": " << r.output;
    const std::vector<float> values = read_planes(out, 3);
    for (size_t k = 0; k < values.size(); ++k)
      EXPECT_NEAR(values[k], reference[k], 1e-5 * (1 + std::abs(reference[k])))
          << backend << " " << k;
  }
}

// Runs render with the given component options and expects exit code `code`, a message
// containing every string of `needles`, and no output files.
void expect_render_failure(const fs::path& out, const std::string& components, int code,
                           const std::vector<std::string>& needles) {
  const CommandResult r = facetool("render" + components + " -o " + quoted(out));
  EXPECT_EQ(r.exit_code, code) << r.output;
  for (const std::string& needle : needles)
    EXPECT_NE(r.output.find(needle), std::string::npos) << "missing '" << needle << "' in:\n"
                                                        << r.output;
  const fs::path shading =
      out.parent_path() / (out.stem().string() + "_shading" + out.extension().string());
  EXPECT_FALSE(fs::exists(out)) << out;
  EXPECT_FALSE(fs::exists(shading)) << shading;
  for (const auto& entry : fs::directory_iterator(out.parent_path()))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST_F(LightCliTest, RenderRejectsBadInputsWithoutWritingAnything) {
  const Scene s = test_scene();
  const int n = s.w * s.h;
  write_exr(file("albedo.exr"), s.w, s.h, {"R", "G", "B"}, s.albedo);
  write_exr(file("normal.exr"), s.w, s.h, {"X", "Y", "Z"}, s.normal);
  write_exr(file("small_normal.exr"), 4, 3, {"X", "Y", "Z"}, std::vector<float>(36, 0.5f));
  write_exr(file("three.exr"), s.w, s.h, {"R", "G", "B"}, s.albedo);
  std::vector<float> nan_normal = s.normal;
  nan_normal[n + 9] = std::numeric_limits<float>::quiet_NaN();  // pixel (2, 1), channel 1
  write_exr(file("nan_normal.exr"), s.w, s.h, {"X", "Y", "Z"}, nan_normal);
  write_test_light(file("light.json"), test_light());
  const std::string albedo = " --albedo " + quoted(file("albedo.exr"));
  const std::string normal = " --normal " + quoted(file("normal.exr"));
  const std::string light = " --light " + quoted(file("light.json"));
  const fs::path out = file("out.exr");

  expect_render_failure(out, albedo + " --normal " + quoted(file("small_normal.exr")) + light, 1,
                        {"small_normal.exr", "4x3", "albedo.exr", "7x5"});
  expect_render_failure(out, albedo + normal + " --visibility " + quoted(file("three.exr")) + light,
                        1, {"three.exr", "3 channels", "9 channels"});
  expect_render_failure(out, albedo + " --normal " + quoted(file("nan_normal.exr")) + light, 1,
                        {"nan_normal.exr", "NaN", "(2, 1)"});
  expect_render_failure(out, " --albedo " + quoted(file("absent.png")) + normal + light, 1,
                        {"absent.png", "does not exist"});
  expect_render_failure(out, albedo + normal + " --light " + quoted(file("absent.json")), 1,
                        {"absent.json"});
  expect_render_failure(out, albedo + normal + " --mask " + quoted(file("normal.exr")) + light, 1,
                        {"--mask", "normal.exr"});
  expect_render_failure(file("out.jpg"), albedo + normal + light, 2, {"out.jpg", ".png", ".exr"});
  expect_render_failure(out, albedo + light, 2, {"--normal"});
}

}  // namespace
}  // namespace facetool
