// The light's gain (libs/inference/light_gain.h): the fitted gain is the least-squares scale per
// colour in the mask (checked by perturbing it), one gain for a grey crop, degenerate crops keep
// or clamp the light, and the decomposer's gained shading is what the renderer gives for the
// gained light.
#include <gtest/gtest.h>

#include <cmath>

#include "core/backend/backend.h"
#include "core/backend/registry.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/renderer_plugin.h"
#include "libs/inference/decomposer.h"
#include "libs/inference/light_gain.h"
#include "libs/model/landmark_normals.h"
#include "tests/support/paper_plugins.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

// The squared error of gain x reconstruction against the image in the mask, channel c, plainly.
double masked_error(const std::vector<float>& r, const std::vector<float>& image, const std::vector<float>& mask,
                    int c, double gain) {
  const size_t plane = mask.size();
  double sum = 0;
  for (size_t p = 0; p < plane; ++p)
    if (mask[p] > 0.5f) {
      const double d = gain * r[c * plane + p] - image[c * plane + p];
      sum += d * d;
    }
  return sum;
}

TEST(FitLightGain, RecoversTheGainsOfAScaledReconstructionInTheMask) {
  const size_t plane = 400;
  const std::vector<float> r = testing::random_values(3 * plane, 1, 0.05f, 1.0f);
  std::vector<float> image = testing::random_values(3 * plane, 2, 0.0f, 5.0f);  // garbage outside the mask
  std::vector<float> mask(plane, 0.0f);
  const float truth[3] = {1.3f, 0.8f, 2.5f};
  for (size_t p = 0; p < plane; p += 3) {
    mask[p] = 0.9f;
    for (int c = 0; c < 3; ++c) image[c * plane + p] = truth[c] * r[c * plane + p];
  }
  const std::array<float, 3> gain = fit_light_gain(r.data(), image.data(), mask.data(), plane);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(gain[c], truth[c], 1e-5) << c;
}

// With noise no gain explains the image exactly; the fitted one is where the error is least.
TEST(FitLightGain, IsTheLeastSquaresScale) {
  const size_t plane = 1000;
  const std::vector<float> r = testing::random_values(3 * plane, 3, 0.0f, 1.0f);
  std::vector<float> image = testing::random_values(3 * plane, 4, -0.2f, 0.2f);
  const std::vector<float> mask = testing::random_values(plane, 5, 0.0f, 1.0f);
  for (size_t k = 0; k < image.size(); ++k) image[k] += 0.7f * r[k];
  const std::array<float, 3> gain = fit_light_gain(r.data(), image.data(), mask.data(), plane);
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(gain[c], 0.5f);
    const double best = masked_error(r, image, mask, c, gain[c]);
    for (const double step : {-1e-2, -1e-3, 1e-3, 1e-2}) EXPECT_LT(best, masked_error(r, image, mask, c, gain[c] + step));
  }
}

// A grey crop (three equal channels) gets one gain, the least-squares one over all three colours,
// even when the reconstruction is coloured; a crop differing in one pixel gets three.
TEST(FitLightGain, AGreyCropGetsOneGainForTheThreeColours) {
  const size_t plane = 300;
  const std::vector<float> r = testing::random_values(3 * plane, 7, 0.1f, 1.0f);
  std::vector<float> image(3 * plane);
  const std::vector<float> grey = testing::random_values(plane, 8, 0.0f, 1.0f);
  for (int c = 0; c < 3; ++c) std::copy(grey.begin(), grey.end(), image.begin() + c * plane);
  const std::vector<float> mask(plane, 1.0f);
  const std::array<float, 3> gain = fit_light_gain(r.data(), image.data(), mask.data(), plane);
  EXPECT_EQ(gain[0], gain[1]);
  EXPECT_EQ(gain[1], gain[2]);
  auto total = [&](double g) {
    double sum = 0;
    for (int c = 0; c < 3; ++c) sum += masked_error(r, image, mask, c, g);
    return sum;
  };
  for (const double step : {-1e-2, -1e-3, 1e-3, 1e-2}) EXPECT_LT(total(gain[0]), total(gain[0] + step));
  image[plane + 5] += 0.01f;  // no longer grey
  const std::array<float, 3> colour = fit_light_gain(r.data(), image.data(), mask.data(), plane);
  EXPECT_FALSE(colour[0] == colour[1] && colour[1] == colour[2]);
}

TEST(FitLightGain, DegenerateCropsKeepOrClampTheLight) {
  const size_t plane = 200;
  const std::vector<float> r = testing::random_values(3 * plane, 6, 0.1f, 1.0f);
  std::vector<float> mask(plane, 1.0f);
  std::vector<float> bright(3 * plane), dark(3 * plane, 0.0f);
  for (size_t k = 0; k < bright.size(); ++k) bright[k] = 100.0f * r[k];
  EXPECT_EQ(fit_light_gain(r.data(), bright.data(), mask.data(), plane), (std::array<float, 3>{kMaxLightGain, kMaxLightGain, kMaxLightGain}));
  EXPECT_EQ(fit_light_gain(r.data(), dark.data(), mask.data(), plane), (std::array<float, 3>{kMinLightGain, kMinLightGain, kMinLightGain}));
  std::vector<float> black(3 * plane, 0.0f);  // nothing rendered: no gain to fit
  EXPECT_EQ(fit_light_gain(black.data(), bright.data(), mask.data(), plane), (std::array<float, 3>{1, 1, 1}));
  std::fill(mask.begin(), mask.end(), 0.0f);
  std::fill_n(mask.begin(), kMinLightGainPixels - 1, 1.0f);  // too few face pixels
  EXPECT_EQ(fit_light_gain(r.data(), bright.data(), mask.data(), plane), (std::array<float, 3>{1, 1, 1}));
  mask[kMinLightGainPixels - 1] = 1.0f;
  EXPECT_EQ(fit_light_gain(r.data(), bright.data(), mask.data(), plane)[0], kMaxLightGain);
}

// A head whose mask covers the crop's left half (its normals face the camera), with the
// landmarks it was "fitted" to: any 68 points, the face lying on them.
LandmarkNormals left_half_head(int s) {
  LandmarkNormals head;
  head.crop_size = s;
  head.grid = 4;
  head.blend = 1.0f;
  head.weights.assign(static_cast<size_t>(LandmarkNormals::kFeatures) * 4 * 4 * 4, 0.0f);
  float* constant = head.weights.data() + static_cast<size_t>(LandmarkNormals::kFeatures - 1) * 4 * 4 * 4;
  for (int cy = 0; cy < 4; ++cy)
    for (int cx = 0; cx < 2; ++cx) {
      constant[(cy * 4 + cx) * 4 + 2] = 1.0f;  // normal z x mask
      constant[(cy * 4 + cx) * 4 + 3] = 1.0f;  // mask
    }
  for (int k = 0; k < LandmarkNormals::kLandmarks; ++k) {
    head.mean_landmarks.push_back(2.0f + static_cast<float>((k * 7) % 13));
    head.mean_landmarks.push_back(3.0f + static_cast<float>((k * 5) % 11));
  }
  return head;
}

// A paper network of width 8 at s x s with random weights, the renderer, and left_half_head(s)
// with its mask (from its own mean landmarks).
struct HeadedNetwork {
  HeadedNetwork(Backend& backend, int s, uint64_t seed)
      : plugins(FACETOOL_PAPER_NETWORK_PLUGIN, FACETOOL_SH_RENDERER_PLUGIN), head(left_half_head(s)) {
    if (!plugins.network || !plugins.renderer) return;
    plugins.network->build(backend, NetworkConfig{8, s});
    plugins.network->init_random(seed);
    std::vector<float> head_normal;
    head.predict(head.mean_landmarks.data(), head_normal, mask);
  }
  testing::PaperPlugins plugins;
  LandmarkNormals head;
  std::vector<float> mask;
};

// The decomposer's light, shading and reconstruction with the gain are those without it times
// the least-squares gains in the head's mask (the crop's face made a colour scale of a
// reconstruction, so the gains are far from 1); the renderer given the gained light renders the
// same shading (it is linear in the light); albedo and normals do not change; without landmarks
// (no face mask) the light stays the network's.
TEST(LightGain, DecomposerScalesTheLightAndItsRenderByTheFittedGains) {
  Backend& backend = get_backend("cpu");
  const int s = 16;
  const size_t plane = static_cast<size_t>(s) * s;
  HeadedNetwork net(backend, s, 3);
  testing::PaperPlugins& plugins = net.plugins;
  ASSERT_TRUE(plugins.network && plugins.renderer);
  const LandmarkNormals& head = net.head;
  const std::vector<float>& mask = net.mask;
  size_t inside = 0;
  for (size_t p = 0; p < plane; ++p) inside += mask[p] > 0.5f;
  ASSERT_GT(inside, kMinLightGainPixels);
  ASSERT_LT(inside, plane * 3 / 4);  // the right side is outside

  Decomposer decomposer(*plugins.network, *plugins.renderer);
  decomposer.set_landmark_normals(&head);
  EXPECT_TRUE(decomposer.light_gain());  // the default
  decomposer.set_light_solve(false);     // the gain alone (with the solve it serves unsolved crops)
  std::vector<float> crop = testing::random_values(3 * plane, 10, 0.0f, 1.0f);
  decomposer.set_light_gain(false);
  const Decomposition plain = decomposer.run(backend, crop, 1, &head.mean_landmarks);
  // The crop's face: the plain reconstruction in colours scaled by `truth`; elsewhere noise.
  const float truth[3] = {1.25f, 0.8f, 1.1f};
  for (int c = 0; c < 3; ++c)
    for (size_t p = 0; p < plane; ++p)
      if (mask[p] > 0.5f) crop[c * plane + p] = truth[c] * plain.reconstruction[c * plane + p];
  const Decomposition before = decomposer.run(backend, crop, 1, &head.mean_landmarks);
  decomposer.set_light_gain(true);
  const Decomposition after = decomposer.run(backend, crop, 1, &head.mean_landmarks);
  EXPECT_EQ(after.albedo, before.albedo);
  EXPECT_EQ(after.normal, before.normal);
  for (int c = 0; c < 3; ++c) {
    // The network answers the changed crop differently, so the gain is measured against `before`.
    double cross = 0, square = 0;
    for (size_t p = 0; p < plane; ++p)
      if (mask[p] > 0.5f) {
        cross += double(before.reconstruction[c * plane + p]) * crop[c * plane + p];
        square += double(before.reconstruction[c * plane + p]) * before.reconstruction[c * plane + p];
      }
    const double gain = cross / square;
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(after.light[c * 9 + k], gain * before.light[c * 9 + k], 1e-5 * std::abs(gain * before.light[c * 9 + k]) + 1e-7);
    for (size_t p = 0; p < plane; ++p) {
      EXPECT_NEAR(after.shading[c * plane + p], gain * before.shading[c * plane + p], 1e-5 * std::abs(gain * before.shading[c * plane + p]) + 1e-7);
      EXPECT_NEAR(after.reconstruction[c * plane + p], gain * before.reconstruction[c * plane + p], 1e-5 * std::abs(gain * before.reconstruction[c * plane + p]) + 1e-7);
    }
    EXPECT_LE(masked_error(after.reconstruction, crop, mask, c, 1.0), masked_error(before.reconstruction, crop, mask, c, 1.0));
  }
  // The renderer, given the gained light, the network's albedo and visibility and the blended normals.
  RenderInputs in{Tensor::from_host(backend, Shape{1, 3, s, s}, after.albedo),
                  Tensor::from_host(backend, Shape{1, 3, s, s}, after.normal),
                  Tensor::from_host(backend, Shape{1, 9, s, s}, after.visibility),
                  Tensor::from_host(backend, Shape{1, 27}, after.light), Tensor()};
  RenderOutputs out;
  plugins.renderer->forward(in, out);
  const std::vector<float> shading = out.shading.to_host();
  for (size_t k = 0; k < shading.size(); ++k) EXPECT_NEAR(shading[k], after.shading[k], 1e-5 * std::abs(shading[k]) + 1e-6) << k;
  // Without landmarks there is no face mask: the light stays the network's.
  const Decomposition unmasked = decomposer.run(backend, crop, 1);
  decomposer.set_light_gain(false);
  EXPECT_EQ(unmasked.light, decomposer.run(backend, crop, 1).light);
}

// The light solve in the decomposer (libs/light/light_from_shading.h): a crop whose face is the
// renderer's image of the network's own layers under a distant light gets a solved light in place
// of the network's (the solve's accuracy is tested in tests/light); the shading is the renderer's
// for the solved light; the albedo is the crop over the shading where lit and the
// reconstruction is albedo x shading; normals and visibility do not change; unsolved crops (no
// landmarks) keep the network's light.
TEST(LightSolve, DecomposerRendersTheSolvedLightAndTheAlbedoFollows) {
  Backend& backend = get_backend("cpu");
  const int s = 32;
  const size_t plane = static_cast<size_t>(s) * s;
  HeadedNetwork net(backend, s, 5);
  testing::PaperPlugins& plugins = net.plugins;
  ASSERT_TRUE(plugins.network && plugins.renderer);
  const LandmarkNormals& head = net.head;
  const std::vector<float>& mask = net.mask;
  Decomposer decomposer(*plugins.network, *plugins.renderer);
  decomposer.set_landmark_normals(&head);
  EXPECT_TRUE(decomposer.light_solve());  // the default
  std::vector<float> crop = testing::random_values(3 * plane, 11, 0.2f, 0.8f);
  decomposer.set_light_solve(false);
  const Decomposition network = decomposer.run(backend, crop, 1, &head.mean_landmarks);
  // The face: the network's own layers (with the head's normals blended in) under a side light.
  DistantLight truth;
  truth.direction = {0.5, 0.3, std::sqrt(1 - 0.25 - 0.09)};
  truth.ambient = {0.05, 0.05, 0.05};
  truth.intensity = {2.0, 2.0, 2.0};
  const sh::RgbLight light = sh_light(truth);
  std::vector<float> light_f(light.begin(), light.end());
  RenderInputs in{Tensor::from_host(backend, Shape{1, 3, s, s}, network.albedo),
                  Tensor::from_host(backend, Shape{1, 3, s, s}, network.normal),
                  Tensor::from_host(backend, Shape{1, 9, s, s}, network.visibility),
                  Tensor::from_host(backend, Shape{1, 27}, light_f), Tensor()};
  RenderOutputs rendered;
  plugins.renderer->forward(in, rendered);
  const std::vector<float> image = rendered.image.to_host();
  for (size_t k = 0; k < 3 * plane; ++k)
    if (mask[k % plane] > 0.5f) crop[k] = image[k];
  const Decomposition before = decomposer.run(backend, crop, 1, &head.mean_landmarks);
  decomposer.set_light_solve(true);
  const Decomposition after = decomposer.run(backend, crop, 1, &head.mean_landmarks);
  ASSERT_EQ(after.light_solve.size(), 1u);
  ASSERT_TRUE(after.light_solve[0].solved);
  EXPECT_EQ(after.normal, before.normal);
  EXPECT_EQ(after.visibility, before.visibility);
  EXPECT_NE(after.light, before.light);
  const sh::RgbLight solved = sh_light(after.light_solve[0]);
  for (int k = 0; k < 27; ++k) EXPECT_FLOAT_EQ(after.light[k], static_cast<float>(solved[k])) << k;
  // The renderer's shading for the solved light, and the reconstruction albedo x shading.
  RenderInputs again{Tensor::from_host(backend, Shape{1, 3, s, s}, after.albedo),
                     Tensor::from_host(backend, Shape{1, 3, s, s}, after.normal),
                     Tensor::from_host(backend, Shape{1, 9, s, s}, after.visibility),
                     Tensor::from_host(backend, Shape{1, 27}, after.light), Tensor()};
  RenderOutputs out;
  plugins.renderer->forward(again, out);
  const std::vector<float> shading = out.shading.to_host();
  for (size_t k = 0; k < 3 * plane; ++k) {
    EXPECT_NEAR(after.shading[k], shading[k], 1e-5 * std::abs(shading[k]) + 1e-6) << k;
    EXPECT_FLOAT_EQ(after.reconstruction[k], after.albedo[k] * after.shading[k]) << k;
  }
  // Without landmarks there is no face mask: nothing is solved and the light is the network's.
  const Decomposition unmasked = decomposer.run(backend, crop, 1);
  ASSERT_EQ(unmasked.light_solve.size(), 1u);
  EXPECT_FALSE(unmasked.light_solve[0].solved);
  decomposer.set_light_solve(false);
  EXPECT_EQ(unmasked.light, decomposer.run(backend, crop, 1).light);
}

}  // namespace
}  // namespace facetool
