// The relit-input augmentation: relit rows against the reference renderer, exposure, the draws.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "core/backend/registry.h"
#include "core/sh/sh_types.h"
#include "core/util/error.h"
#include "libs/data/training_sample.h"
#include "libs/io/image_io.h"
#include "libs/relight/relight_math.h"
#include "libs/synth/component_renderer.h"
#include "libs/train/relit_inputs.h"
#include "libs/train/training_config.h"

namespace facetool {
namespace {

Backend& cpu() { return get_backend("cpu"); }

constexpr int kRows = 4, kH = 9, kW = 11;
constexpr size_t kPlane = static_cast<size_t>(kH) * kW;

// A batch rendered from its own labels by the reference renderer: random albedo, normals facing
// the camera side (none in the first column: unlabelled pixels), a visibility that shades some
// directions, and a warm light from the upper left with ambient.
struct Rendered {
  SyntheticBatch batch;
  std::vector<float> albedo, normal, visibility, light, image;
};

Rendered rendered_batch(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Rendered r;
  r.albedo.resize(kRows * 3 * kPlane);
  r.normal.assign(kRows * 3 * kPlane, 0.0f);
  r.visibility.assign(kRows * 9 * kPlane, 0.0f);
  r.light.resize(kRows * sh::kLightCoeffCount);
  r.image.resize(kRows * 3 * kPlane);
  const auto renderer = make_reference_renderer();
  for (int n = 0; n < kRows; ++n) {
    for (size_t p = 0; p < kPlane; ++p) {
      for (int c = 0; c < 3; ++c) r.albedo[(n * 3 + c) * kPlane + p] = 0.2f + 0.6f * u(rng);
      if (p % kW == 0) continue;
      float x = 1.6f * u(rng) - 0.8f, y = 1.6f * u(rng) - 0.8f, z = 0.5f + u(rng);
      const float len = std::sqrt(x * x + y * y + z * z);
      r.normal[(n * 3 + 0) * kPlane + p] = x / len;
      r.normal[(n * 3 + 1) * kPlane + p] = y / len;
      r.normal[(n * 3 + 2) * kPlane + p] = z / len;
      const float open = 0.7f + 0.3f * u(rng);
      r.visibility[(n * 9 + 0) * kPlane + p] = static_cast<float>(open * 2 * std::sqrt(M_PI));
      r.visibility[(n * 9 + 2) * kPlane + p] = 0.3f * u(rng);  // more open upwards
    }
    const sh::RgbLight base = one_sided_light({-0.5, 0.5, std::sqrt(0.5)}, 0.3);
    const double tint[3] = {1.2, 1.0, 0.8};
    for (int i = 0; i < sh::kLightCoeffCount; ++i)
      r.light[n * sh::kLightCoeffCount + i] = static_cast<float>(base[i] * tint[i / sh::kCoeffCount]);
    sh::RgbLight l{};
    for (int i = 0; i < sh::kLightCoeffCount; ++i) l[i] = r.light[n * sh::kLightCoeffCount + i];
    renderer->render(static_cast<int>(kPlane), r.albedo.data() + n * 3 * kPlane, r.normal.data() + n * 3 * kPlane,
                     r.visibility.data() + n * 9 * kPlane, l, r.image.data() + n * 3 * kPlane);
  }
  r.batch.image = Tensor::from_host(cpu(), Shape{kRows, 3, kH, kW}, r.image);
  r.batch.albedo = Tensor::from_host(cpu(), Shape{kRows, 3, kH, kW}, r.albedo);
  r.batch.normal = Tensor::from_host(cpu(), Shape{kRows, 3, kH, kW}, r.normal);
  r.batch.visibility = Tensor::from_host(cpu(), Shape{kRows, 9, kH, kW}, r.visibility);
  r.batch.mask = Tensor::full(cpu(), Shape{kRows, 1, kH, kW}, 1.0f);
  r.batch.light = Tensor::from_host(cpu(), Shape{kRows, sh::kLightCoeffCount}, r.light);
  return r;
}

// Every row relit: where the old shading is well lit (and further than the feather from the
// unlabelled column), the relit pixel is the photo times the guarded ratio of the reference renderer's shading under the new light label to that under the
// old one (relative 1e-4); unlabelled pixels keep their value; the mean shading over the labelled
// pixels is the old one per channel; the new light's first band points along the row's draw.
TEST(RelitInputs, RelitRowsAreTheRenderersRatioUnderTheNewLight) {
  Rendered r = rendered_batch(3);
  relight_some_rows(r.batch, 5, 2, 1, 1.0);
  const std::vector<float> image = r.batch.image.to_host(), light = r.batch.light.to_host();
  const auto renderer = make_reference_renderer();
  const std::vector<float> white(3 * kPlane, 1.0f);
  int checked = 0, darker = 0, brighter = 0;
  for (int n = 0; n < kRows; ++n) {
    sh::RgbLight old_light{}, new_light{};
    for (int i = 0; i < sh::kLightCoeffCount; ++i) {
      old_light[i] = r.light[n * sh::kLightCoeffCount + i];
      new_light[i] = light[n * sh::kLightCoeffCount + i];
    }
    std::vector<float> old_shading(3 * kPlane), new_shading(3 * kPlane);
    const float* nrm = r.normal.data() + n * 3 * kPlane;
    const float* vis = r.visibility.data() + n * 9 * kPlane;
    renderer->render(static_cast<int>(kPlane), white.data(), nrm, vis, old_light, old_shading.data());
    renderer->render(static_cast<int>(kPlane), white.data(), nrm, vis, new_light, new_shading.data());
    for (int c = 0; c < 3; ++c) {
      double old_sum = 0, new_sum = 0;
      for (size_t p = 0; p < kPlane; ++p) {
        const size_t at = (n * 3 + c) * kPlane + p;
        if (p % kW == 0) {
          EXPECT_EQ(image[at], r.image[at]) << "an unlabelled pixel changed";
          continue;
        }
        old_sum += old_shading[c * kPlane + p];
        new_sum += std::max(0.0f, new_shading[c * kPlane + p]);
        const float o = old_shading[c * kPlane + p], f = new_shading[c * kPlane + p];
        const float gain = (std::max(f, 0.0f) + relight::kDefaultRatioEpsilon) / (o + relight::kDefaultRatioEpsilon);
        if (o < 0.1f || gain > kMaxRelightGain || static_cast<int>(p % kW) <= kRelightFeather) continue;
        EXPECT_NEAR(image[at], r.image[at] * gain, 1e-4 * r.image[at] * gain + 1e-6) << n << " " << c << " " << p;
        ++checked;
        darker += gain < 0.8f;
        brighter += gain > 1.25f;
      }
      EXPECT_NEAR(new_sum / old_sum, 1.0, 1e-3) << "row " << n << " channel " << c << ": exposure moved";
    }
    const RelightDraw d = relight_draw(5, 2, 1, n);
    const sh::Vec3 band1{new_light[3], new_light[1], new_light[2]};  // Y_1^1 ~ x, Y_1^-1 ~ y, Y_1^0 ~ z
    const double len = std::sqrt(band1[0] * band1[0] + band1[1] * band1[1] + band1[2] * band1[2]);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(band1[k] / len, d.direction[k], 1e-5) << "row " << n;
  }
  EXPECT_GT(checked, kRows * 3 * static_cast<int>(kPlane) / 3);
  EXPECT_GT(darker, 0);  // a different light, not the old one again
  EXPECT_GT(brighter, 0);
}

// The hard light: the network's input is the photo times the guarded ratio of the light's exact
// shading (max(n.l, 0) times the visibility function at l, from the SH formulas written out here,
// plus the ambient through the reference renderer) to the old shading, at the scale the light
// label carries; the target (batch.image) and the light label are the SH relighting's; rows'
// draws come from the strobe range. Relative 1e-4 where the old shading is well lit.
TEST(RelitInputs, HardLightRelitsTheInputExactlyAndKeepsTheShTarget) {
  Rendered r = rendered_batch(3);
  relight_some_rows(r.batch, 5, 2, 1, 1.0, 0, RelightLight::kHard);
  ASSERT_TRUE(r.batch.input_image.defined());
  const std::vector<float> input = r.batch.input_image.to_host(), image = r.batch.image.to_host();
  const std::vector<float> light = r.batch.light.to_host();
  const auto renderer = make_reference_renderer();
  const std::vector<float> white(3 * kPlane, 1.0f);
  const double k1 = std::sqrt(3.0 / (4.0 * M_PI)), k2 = std::sqrt(15.0 / M_PI) / 2.0;
  int checked_input = 0, checked_target = 0, shadowed = 0;
  for (int n = 0; n < kRows; ++n) {
    const RelightDraw d = relight_draw(5, 2, 1, n, RelightLight::kHard);
    const double x = d.direction[0], y = d.direction[1], z = d.direction[2];
    const double basis[9] = {0.5 / std::sqrt(M_PI), k1 * y, k1 * z, k1 * x, k2 * x * y, k2 * y * z,
                             std::sqrt(5.0 / M_PI) / 4.0 * (3 * z * z - 1), k2 * x * z, k2 / 2.0 * (x * x - y * y)};
    sh::RgbLight old_light{}, new_light{}, ambient_only{};
    for (int i = 0; i < sh::kLightCoeffCount; ++i) {
      old_light[i] = r.light[n * sh::kLightCoeffCount + i];
      new_light[i] = light[n * sh::kLightCoeffCount + i];
    }
    double scale[3];
    for (int c = 0; c < 3; ++c) {
      const double* b = new_light.data() + c * sh::kCoeffCount;
      scale[c] = std::sqrt(b[1] * b[1] + b[2] * b[2] + b[3] * b[3]) / k1;  // a unit light's band 1 is k1 long
      EXPECT_NEAR(b[3] / (k1 * scale[c]), x, 1e-5);
      EXPECT_NEAR(b[1] / (k1 * scale[c]), y, 1e-5);
      ambient_only[c * sh::kCoeffCount] = static_cast<float>(scale[c] * 2.0 * std::sqrt(M_PI) * d.ambient / M_PI);
    }
    EXPECT_LE(d.ambient, 0.3);
    std::vector<float> old_shading(3 * kPlane), sh_shading(3 * kPlane), ambient_shading(3 * kPlane);
    const float* nrm = r.normal.data() + n * 3 * kPlane;
    const float* vis = r.visibility.data() + n * 9 * kPlane;
    renderer->render(static_cast<int>(kPlane), white.data(), nrm, vis, old_light, old_shading.data());
    renderer->render(static_cast<int>(kPlane), white.data(), nrm, vis, new_light, sh_shading.data());
    renderer->render(static_cast<int>(kPlane), white.data(), nrm, vis, ambient_only, ambient_shading.data());
    for (size_t p = 0; p < kPlane; ++p) {
      if (p % kW == 0 || static_cast<int>(p % kW) <= kRelightFeather) continue;
      const double cosine = nrm[p] * x + nrm[kPlane + p] * y + nrm[2 * kPlane + p] * z;
      double v = 0;
      for (int i = 0; i < 9; ++i) v += vis[i * kPlane + p] * basis[i];
      const double direct = std::max(cosine, 0.0) * std::clamp(v, 0.0, 1.0) / M_PI;
      shadowed += cosine <= 0;
      for (int c = 0; c < 3; ++c) {
        const size_t at = (n * 3 + c) * kPlane + p;
        const double o = old_shading[c * kPlane + p];
        const double hard = scale[c] * direct + ambient_shading[c * kPlane + p];
        const double eps = relight::kDefaultRatioEpsilon;
        const double hard_gain = (hard + eps) / (o + eps);
        const double sh_gain = (std::max(0.0, double(sh_shading[c * kPlane + p])) + eps) / (o + eps);
        if (o < 0.1) continue;
        if (hard_gain <= kMaxRelightGain) {
          EXPECT_NEAR(input[at], r.image[at] * hard_gain, 1e-4 * r.image[at] * hard_gain + 1e-6) << n << " " << p;
          ++checked_input;
        }
        if (sh_gain <= kMaxRelightGain) {
          EXPECT_NEAR(image[at], r.image[at] * sh_gain, 1e-4 * r.image[at] * sh_gain + 1e-6) << n << " " << p;
          ++checked_target;
        }
      }
    }
  }
  EXPECT_GT(checked_input, kRows * 3 * static_cast<int>(kPlane) / 4);
  EXPECT_GT(checked_target, kRows * 3 * static_cast<int>(kPlane) / 4);
  EXPECT_GT(shadowed, 0);  // some pixels face away from some row's light: the terminator is tested
  // The SH mode leaves input_image undefined: the network reads the target.
  Rendered plain = rendered_batch(3);
  relight_some_rows(plain.batch, 5, 2, 1, 1.0);
  EXPECT_FALSE(plain.batch.input_image.defined());
}

// The strobe range: over many draws the hard light reaches beyond the soft one's elevation
// (-10..40) and azimuth (+-75), and stays within -30..65 and +-90.
TEST(RelitInputs, HardDrawsCoverTheStrobeRange) {
  double lowest = 90, highest = -90, widest = 0;
  for (int64_t row = 0; row < 2000; ++row) {
    const sh::Vec3 d = relight_draw(7, 3, 0, row, RelightLight::kHard).direction;
    const double elevation = std::asin(d[1]) * 180 / M_PI, azimuth = std::atan2(d[0], d[2]) * 180 / M_PI;
    lowest = std::min(lowest, elevation);
    highest = std::max(highest, elevation);
    widest = std::max(widest, std::abs(azimuth));
  }
  EXPECT_LT(lowest, -25);
  EXPECT_GE(lowest, -30);
  EXPECT_GT(highest, 60);
  EXPECT_LE(highest, 65);
  EXPECT_GT(widest, 85);
  EXPECT_LE(widest, 90);
}

// A fraction picks rows by relit_row and leaves the others (image and light) as they were; a
// fraction of 0 and a batch without a light label change nothing.
TEST(RelitInputs, OnlyThePickedLabelledRowsChange) {
  Rendered r = rendered_batch(4);
  for (int64_t first_row : {0, 6}) {
    SyntheticBatch b = r.batch;
    relight_some_rows(b, 9, 1, 0, 0.5, first_row);
    const std::vector<float> image = b.image.to_host(), light = b.light.to_host();
    for (int n = 0; n < kRows; ++n) {
      bool same = true;
      for (size_t i = 0; i < 3 * kPlane; ++i) same &= image[n * 3 * kPlane + i] == r.image[n * 3 * kPlane + i];
      for (int i = 0; i < sh::kLightCoeffCount; ++i)
        same &= light[n * sh::kLightCoeffCount + i] == r.light[n * sh::kLightCoeffCount + i];
      EXPECT_EQ(!same, relit_row(9, 1, 0, first_row + n, 0.5)) << first_row << " " << n;
    }
  }
  SyntheticBatch none = r.batch;
  relight_some_rows(none, 9, 1, 0, 0.0);
  EXPECT_EQ(none.image.to_host(), r.image);
  SyntheticBatch unlit = r.batch;
  unlit.light = Tensor::zeros(cpu(), Shape{kRows, sh::kLightCoeffCount});
  relight_some_rows(unlit, 9, 1, 0, 1.0);
  EXPECT_EQ(unlit.image.to_host(), r.image);
}

// The draws cover the documented ranges (1,000 draws reach within 5 degrees of each end) and stay
// inside them; the same arguments give the same draw.
TEST(RelitInputs, TheDrawsCoverTheirRanges) {
  double az_lo = 90, az_hi = -90, el_lo = 90, el_hi = -90, am_lo = 1, am_hi = 0;
  for (int64_t step = 0; step < 50; ++step)
    for (int64_t row = 0; row < 20; ++row) {
      const RelightDraw d = relight_draw(1, step, 0, row);
      const double az = std::atan2(d.direction[0], d.direction[2]) * 180 / M_PI;
      const double el = std::asin(d.direction[1]) * 180 / M_PI;
      az_lo = std::min(az_lo, az), az_hi = std::max(az_hi, az);
      el_lo = std::min(el_lo, el), el_hi = std::max(el_hi, el);
      am_lo = std::min(am_lo, d.ambient), am_hi = std::max(am_hi, d.ambient);
      EXPECT_EQ(relight_draw(1, step, 0, row).direction, d.direction);
    }
  EXPECT_GE(az_lo, -75.0 - 1e-9);
  EXPECT_LE(az_hi, 75.0 + 1e-9);
  EXPECT_LT(az_lo, -70.0);
  EXPECT_GT(az_hi, 70.0);
  EXPECT_GE(el_lo, -10.0 - 1e-9);
  EXPECT_LE(el_hi, 40.0 + 1e-9);
  EXPECT_LT(el_lo, -5.0);
  EXPECT_GT(el_hi, 35.0);
  EXPECT_GE(am_lo, 0.05);
  EXPECT_LE(am_hi, 0.4);
  EXPECT_LT(am_lo, 0.07);
  EXPECT_GT(am_hi, 0.38);
}

// The ambient term of one_sided_light gives a facing, unoccluded surface `ambient` times the
// irradiance of the distant light (the reference renderer with albedo pi: the irradiance).
TEST(RelitInputs, TheAmbientTermIsAFractionOfTheLightsIrradiance) {
  const auto renderer = make_reference_renderer();
  const std::vector<float> albedo(3, static_cast<float>(M_PI)), up{0.0f, 0.0f, 1.0f},
      open{static_cast<float>(2 * std::sqrt(M_PI)), 0, 0, 0, 0, 0, 0, 0, 0};
  float facing[3], away[3];
  renderer->render(1, albedo.data(), up.data(), open.data(), one_sided_light({0, 0, 1}, 0.25), facing);
  renderer->render(1, albedo.data(), up.data(), open.data(), one_sided_light({0, 0, -1}, 0.25), away);
  // Order-2 SH of a delta light through the clamped cosine: sum_l A_l (2l + 1) / (4 pi) (+-1)^l
  // with A = (pi, 2 pi / 3, pi / 4): 1.0625 facing it, 0.0625 facing away (the true 1 and 0).
  EXPECT_NEAR(facing[0], 1.0625 + 0.25, 1e-5);
  EXPECT_NEAR(away[0], 0.0625 + 0.25, 1e-5);
  for (int c = 1; c < 3; ++c) EXPECT_EQ(facing[c], facing[0]);
}

TEST(RelitInputs, TheSourceKeyNeedsLabels) {
  const std::string head = R"({"name": "x", "steps": 1, "sources": [{"name": "s", "directory": "d", )";
  const std::string tail = R"("terms": {"albedo": 1}}]})";
  EXPECT_EQ(parse_training_config(head + tail, "a.json").sources[0].relight_fraction, 0.0);
  EXPECT_EQ(parse_training_config(head + R"("relight_fraction": 0.4, )" + tail, "a.json").sources[0].relight_fraction, 0.4);
  EXPECT_EQ(parse_training_config(head + tail, "a.json").sources[0].relight_light, "sh");
  EXPECT_EQ(parse_training_config(head + R"("relight_light": "hard", )" + tail, "a.json").sources[0].relight_light, "hard");
  for (const std::string bad : {R"("relight_fraction": 2, )", R"("kind": "real", "relight_fraction": 0.5, )",
                                R"("relight_fraction": 0.5, "relight_light": "soft", )"}) {
    try {
      parse_training_config(head + bad + tail, "b.json");
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("relight_"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("b.json"), std::string::npos) << e.what();
    }
  }
}

// Not a check: draws FACETOOL_RELIT_SAMPLES' first 8 pseudo-labelled samples (sample_*.exr) as
// they are (top row) and relit (bottom row, every row relit) into FACETOOL_RELIT_PICTURE, for
// looking at; with FACETOOL_RELIT_LIGHT=hard the SH target (middle) and the hard input (bottom).
// Run: FACETOOL_RELIT_SAMPLES=DIR FACETOOL_RELIT_PICTURE=out.png
// relit_inputs_test --gtest_also_run_disabled_tests --gtest_filter='*DrawRelit*'
TEST(RelitInputs, DISABLED_DrawRelitRealSamples) {
  const char* dir = std::getenv("FACETOOL_RELIT_SAMPLES");
  const char* out = std::getenv("FACETOOL_RELIT_PICTURE");
  ASSERT_TRUE(dir && out) << "set FACETOOL_RELIT_SAMPLES and FACETOOL_RELIT_PICTURE";
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename().string().rfind("sample_", 0) == 0) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  files.resize(std::min<size_t>(files.size(), 8));
  ASSERT_FALSE(files.empty());
  std::vector<TrainingSample> samples;
  for (const std::string& f : files) samples.push_back(read_training_sample(f, true));
  const int w = samples[0].width, h = samples[0].height, n = static_cast<int>(samples.size());
  const size_t plane = static_cast<size_t>(w) * h;
  auto stack = [&](auto member, int channels) {
    std::vector<float> v;
    for (const TrainingSample& s : samples) v.insert(v.end(), (s.*member).begin(), (s.*member).end());
    return Tensor::from_host(cpu(), Shape{n, channels, h, w}, v);
  };
  SyntheticBatch b;
  b.image = stack(&TrainingSample::image, 3);
  b.normal = stack(&TrainingSample::normal, 3);
  b.visibility = stack(&TrainingSample::visibility, 9);
  b.mask = stack(&TrainingSample::mask, 1);
  std::vector<float> light;
  for (const TrainingSample& s : samples) light.insert(light.end(), s.light.begin(), s.light.end());
  b.light = Tensor::from_host(cpu(), Shape{n, sh::kLightCoeffCount}, light);
  const std::vector<float> before = b.image.to_host();
  const char* kind = std::getenv("FACETOOL_RELIT_LIGHT");
  const bool hard = kind && std::string(kind) == "hard";
  relight_some_rows(b, 1, 0, 1, 1.0, 0, hard ? RelightLight::kHard : RelightLight::kSh);
  const std::vector<float> after = b.image.to_host();
  const std::vector<float> input = hard ? b.input_image.to_host() : after;
  const int rows = hard ? 3 : 2;
  RgbImage sheet;
  sheet.width = n * w;
  sheet.height = rows * h;
  sheet.pixels.assign(static_cast<size_t>(sheet.width) * sheet.height * 3, 0.0f);
  for (int k = 0; k < n; ++k)
    for (int row = 0; row < rows; ++row)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < 3; ++c)
            sheet.pixels[((static_cast<size_t>(row * h + y)) * sheet.width + k * w + x) * 3 + c] =
                (row == 0 ? before : row == 1 ? after : input)[(static_cast<size_t>(k) * 3 + c) * plane +
                                                                  static_cast<size_t>(y) * w + x];
  write_png_atomically(out, sheet);
}

}  // namespace
}  // namespace facetool
