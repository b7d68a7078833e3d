// Mirror averaging: the mirrored batch, the sign rule of SH coefficients (against quadrature), and
// the decomposer's answer for a mirrored crop being the mirror of its answer for the crop.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/backend/backend.h"
#include "core/backend/registry.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/renderer_plugin.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sphere_samples.h"
#include "libs/inference/decomposer.h"
#include "libs/inference/mirror_average.h"
#include "tests/support/paper_plugins.h"

namespace facetool {
namespace {

std::vector<float> random_values(size_t count, unsigned seed, float lo = -1.0f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(count);
  for (float& x : v) x = u(rng);
  return v;
}

size_t at(int n, int c, int y, int x, int channels, int size) {
  return ((static_cast<size_t>(n) * channels + c) * size + y) * size + x;
}

TEST(MirrorAverage, MirrorImagesAreFlippedWithThePriorNormalsXNegated) {
  const int n = 2, c = 6, s = 5;  // RGB, then a normal-map prior from channel 3
  const std::vector<float> images = random_values(static_cast<size_t>(n) * c * s * s, 1);
  const std::vector<float> both = with_mirror_images(images, n, c, s, 3);
  ASSERT_EQ(both.size(), 2 * images.size());
  for (int i = 0; i < n; ++i)
    for (int ch = 0; ch < c; ++ch)
      for (int y = 0; y < s; ++y)
        for (int x = 0; x < s; ++x) {
          const float value = images[at(i, ch, y, x, c, s)];
          EXPECT_EQ(both[at(i, ch, y, x, c, s)], value);
          EXPECT_EQ(both[at(n + i, ch, y, s - 1 - x, c, s)], ch == 3 ? -value : value) << ch;
        }
}

// The SH coefficients of f(-x, y, z), f = sum_i c_i Y_i, by quadrature over 64,000 directions.
std::vector<double> mirrored_by_quadrature(const std::vector<double>& c) {
  const std::vector<sh::Vec3> directions = sh::fibonacci_sphere(sh::kIlluminationSampleCount);
  std::vector<double> out(9, 0.0);
  for (const sh::Vec3& d : directions) {
    double at_mirror[9], here[9];
    sh::sh_basis(-d[0], d[1], d[2], at_mirror);
    sh::sh_basis(d[0], d[1], d[2], here);
    double f = 0;
    for (int i = 0; i < 9; ++i) f += c[i] * at_mirror[i];
    for (int j = 0; j < 9; ++j) out[j] += f * here[j];
  }
  for (double& v : out) v *= 4 * M_PI / directions.size();
  return out;
}

// An answer whose mirror image's answer is exactly its mirror (made independently: flipped maps,
// the normal's x negated, the light's and visibility's coefficients from quadrature of the mirrored
// functions) averages back to itself.
TEST(MirrorAverage, ASymmetricPairAveragesBackToTheAnswer) {
  const int n = 2, s = 4;
  const size_t plane = static_cast<size_t>(s) * s;
  NetworkAnswer one{random_values(n * 3 * plane, 2, 0.0f, 1.0f), random_values(n * 3 * plane, 3),
                    random_values(n * 9 * plane, 4), random_values(n * 27, 5)};
  for (int i = 0; i < n; ++i)  // unit normals
    for (size_t p = 0; p < plane; ++p) {
      float* v = one.normal.data() + i * 3 * plane + p;
      const float len = std::sqrt(v[0] * v[0] + v[plane] * v[plane] + v[2 * plane] * v[2 * plane]);
      for (int k = 0; k < 3; ++k) v[k * plane] /= len;
    }
  NetworkAnswer both = one;
  both.albedo.resize(2 * one.albedo.size());
  both.normal.resize(2 * one.normal.size());
  both.visibility.resize(2 * one.visibility.size());
  both.light.resize(2 * one.light.size());
  for (int i = 0; i < n; ++i) {
    for (int y = 0; y < s; ++y)
      for (int x = 0; x < s; ++x) {
        for (int c = 0; c < 3; ++c) {
          both.albedo[at(n + i, c, y, s - 1 - x, 3, s)] = one.albedo[at(i, c, y, x, 3, s)];
          both.normal[at(n + i, c, y, s - 1 - x, 3, s)] = (c == 0 ? -1 : 1) * one.normal[at(i, c, y, x, 3, s)];
        }
        std::vector<double> coefficients(9);
        for (int k = 0; k < 9; ++k) coefficients[k] = one.visibility[at(i, k, y, x, 9, s)];
        const std::vector<double> mirrored = mirrored_by_quadrature(coefficients);
        for (int k = 0; k < 9; ++k) both.visibility[at(n + i, k, y, s - 1 - x, 9, s)] = static_cast<float>(mirrored[k]);
      }
    for (int channel = 0; channel < 3; ++channel) {
      std::vector<double> coefficients(one.light.begin() + i * 27 + channel * 9,
                                       one.light.begin() + i * 27 + channel * 9 + 9);
      const std::vector<double> mirrored = mirrored_by_quadrature(coefficients);
      for (int k = 0; k < 9; ++k) both.light[(n + i) * 27 + channel * 9 + k] = static_cast<float>(mirrored[k]);
    }
  }
  const NetworkAnswer averaged = average_with_mirror(both, n, s);
  // Tolerances: float storage (1e-6) and the quadrature of degree-4 products on 64,000 points (1e-3).
  for (size_t k = 0; k < one.albedo.size(); ++k) EXPECT_NEAR(averaged.albedo[k], one.albedo[k], 1e-6);
  for (size_t k = 0; k < one.normal.size(); ++k) EXPECT_NEAR(averaged.normal[k], one.normal[k], 1e-6);
  for (size_t k = 0; k < one.visibility.size(); ++k) EXPECT_NEAR(averaged.visibility[k], one.visibility[k], 1e-3);
  for (size_t k = 0; k < one.light.size(); ++k) EXPECT_NEAR(averaged.light[k], one.light[k], 1e-3);
}

// Two unrelated answers: each value is the mean of the answer's and the mirrored answer's, read
// at the mirrored pixel; normals normalised after.
TEST(MirrorAverage, AnswersAreAveragedAtTheMirroredPixel) {
  const int n = 1, s = 3;
  const size_t plane = static_cast<size_t>(s) * s;
  const NetworkAnswer both{random_values(2 * 3 * plane, 6, 0.0f, 1.0f), random_values(2 * 3 * plane, 7),
                           random_values(2 * 9 * plane, 8), random_values(2 * 27, 9)};
  const NetworkAnswer out = average_with_mirror(both, n, s);
  for (int y = 0; y < s; ++y)
    for (int x = 0; x < s; ++x) {
      for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(out.albedo[at(0, c, y, x, 3, s)],
                        0.5f * (both.albedo[at(0, c, y, x, 3, s)] + both.albedo[at(1, c, y, s - 1 - x, 3, s)]));
      double sum[3], length = 0;
      for (int c = 0; c < 3; ++c) {
        sum[c] = both.normal[at(0, c, y, x, 3, s)] + (c == 0 ? -1.0 : 1.0) * both.normal[at(1, c, y, s - 1 - x, 3, s)];
        length += sum[c] * sum[c];
      }
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.normal[at(0, c, y, x, 3, s)], sum[c] / std::sqrt(length), 1e-5);
      EXPECT_FLOAT_EQ(out.visibility[at(0, 0, y, x, 9, s)],
                      0.5f * (both.visibility[at(0, 0, y, x, 9, s)] + both.visibility[at(1, 0, y, s - 1 - x, 9, s)]));
      EXPECT_FLOAT_EQ(out.visibility[at(0, 3, y, x, 9, s)],
                      0.5f * (both.visibility[at(0, 3, y, x, 9, s)] - both.visibility[at(1, 3, y, s - 1 - x, 9, s)]));
    }
  EXPECT_FLOAT_EQ(out.light[9 + 7], 0.5f * (both.light[9 + 7] - both.light[27 + 9 + 7]));
  EXPECT_FLOAT_EQ(out.light[18 + 8], 0.5f * (both.light[18 + 8] + both.light[27 + 18 + 8]));
}

// The averaged decomposition of a mirrored crop is the mirror of the crop's (the network alone,
// with random weights, is far from it): the renderer's shading included, which checks the light's
// and visibility's sign rule against the renderer's own SH.
TEST(MirrorAverage, DecomposerAnswersAMirroredCropWithTheMirrorOfItsAnswer) {
  Backend& backend = get_backend("cpu");
  testing::PaperPlugins plugins(FACETOOL_PAPER_NETWORK_PLUGIN, FACETOOL_SH_RENDERER_PLUGIN);
  ASSERT_TRUE(plugins.network && plugins.renderer);
  const int s = 16;
  plugins.network->build(backend, NetworkConfig{8, s});
  plugins.network->init_random(3);
  Decomposer decomposer(*plugins.network, *plugins.renderer);
  const std::vector<float> crop = random_values(3 * s * s, 10, 0.0f, 1.0f);
  const std::vector<float> pair = with_mirror_images(crop, 1, 3, s, -1);
  const std::vector<float> mirrored(pair.begin() + 3 * s * s, pair.end());
  auto worst_mirror_difference = [&](bool average) {
    decomposer.set_mirror_average(average);
    const Decomposition a = decomposer.run(backend, crop, 1);
    const Decomposition b = decomposer.run(backend, mirrored, 1);
    double worst = 0;
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < s; ++y)
        for (int x = 0; x < s; ++x) {
          const size_t here = at(0, c, y, x, 3, s), there = at(0, c, y, s - 1 - x, 3, s);
          worst = std::max(worst, std::abs(double(a.albedo[here]) - b.albedo[there]));
          worst = std::max(worst, std::abs(double(a.normal[here]) - (c == 0 ? -1 : 1) * b.normal[there]));
          worst = std::max(worst, std::abs(double(a.shading[here]) - b.shading[there]));
          worst = std::max(worst, std::abs(double(a.reconstruction[here]) - b.reconstruction[there]));
        }
    return worst;
  };
  EXPECT_TRUE(decomposer.mirror_average());  // the default
  EXPECT_LT(worst_mirror_difference(true), 1e-4);
  EXPECT_GT(worst_mirror_difference(false), 1e-3);  // the test can tell: one pass is not symmetric
}

}  // namespace
}  // namespace facetool
