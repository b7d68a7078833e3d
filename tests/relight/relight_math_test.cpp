// The relighting arithmetic: the guarded ratio against its closed form, orbits, the open hemisphere.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "libs/relight/relight_math.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sh_rotation.h"
#include "core/util/error.h"

namespace facetool::relight {
namespace {

TEST(RelightRatio, OwnShadingGivesExactlyOne) {
  for (float s : {0.0f, 1e-6f, 0.013f, 0.5f, 1.0f, 3.7f, -0.2f})
    EXPECT_EQ(ratio_factor(s, s, kDefaultRatioEpsilon), 1.0f) << "shading " << s;
}

TEST(RelightRatio, GuardBoundsTheRatioWhereTheOldShadingVanishes) {
  const float eps = 0.02f;
  // Old shading zero or negative: the ratio is (new + eps) / eps, finite, not new / 0.
  for (float old_shading : {0.0f, -0.5f, 1e-30f}) {
    const float r = ratio_factor(0.8f, old_shading, eps);
    EXPECT_TRUE(std::isfinite(r));
    EXPECT_NEAR(r, (0.8f + eps) / (std::max(old_shading, 0.0f) + eps), 1e-4f);
    EXPECT_LE(r, (0.8f + eps) / eps * (1 + 1e-6f));
  }
  // Far from zero the guard barely changes the plain ratio: within eps / old relative.
  EXPECT_NEAR(ratio_factor(1.2f, 0.9f, eps), 1.2f / 0.9f, 1.2f / 0.9f * eps / 0.9f);
  // A negative new shading (an SH light dipping below zero) darkens to at most the guard.
  EXPECT_NEAR(ratio_factor(-1.0f, 0.5f, eps), eps / (0.5f + eps), 1e-7f);
}

TEST(RelightRatio, ApplyRatioIsPhotoTimesFactorPerChannel) {
  const size_t plane = 4;
  const std::vector<float> photo = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f, 1.0f, 0.0f, 0.25f};
  const std::vector<float> old_s = {1.0f, 0.5f, 0.0f, 2.0f, 1.0f, 0.5f, 0.0f, 2.0f, 1.0f, 0.5f, 0.0f, 2.0f};
  const std::vector<float> new_s = {0.5f, 0.5f, 1.0f, 1.0f, 2.0f, 0.5f, 0.1f, 4.0f, 0.0f, 0.7f, 3.0f, 1.0f};
  std::vector<float> out(12);
  apply_ratio(photo.data(), old_s.data(), new_s.data(), plane, 0.02f, out.data());
  for (size_t i = 0; i < out.size(); ++i)
    EXPECT_NEAR(out[i], photo[i] * (new_s[i] + 0.02f) / (old_s[i] + 0.02f), 1e-6f) << i;
}

TEST(RelightOrbit, FullTurnReturnsTheLightAndHalfTurnMirrorsX) {
  sh::RgbLight light{};
  for (int i = 0; i < sh::kLightCoeffCount; ++i) light[i] = std::sin(1.0 + 0.7 * i);
  const sh::RgbLight full = orbit_light(light, 24, 24);
  for (int i = 0; i < sh::kLightCoeffCount; ++i) EXPECT_NEAR(full[i], light[i], 1e-12);
  // Half a turn about +Y: the radiance from (x, y, z) now arrives from (-x, y, -z).
  const sh::RgbLight half = orbit_light(light, 6, 12);
  for (const sh::Vec3& d : {sh::Vec3{0.6, 0.0, 0.8}, sh::Vec3{0.0, 1.0, 0.0}, sh::Vec3{-0.48, 0.6, 0.64}}) {
    const sh::ShCoeffs y_new = sh::sh_basis(sh::Vec3{-d[0], d[1], -d[2]}), y_old = sh::sh_basis(d);
    for (int c = 0; c < 3; ++c) {
      double a = 0, b = 0;
      for (int i = 0; i < 9; ++i) {
        a += half[c * 9 + i] * y_new[i];
        b += light[c * 9 + i] * y_old[i];
      }
      EXPECT_NEAR(a, b, 1e-12);
    }
  }
  EXPECT_THROW(orbit_light(light, 0, 0), Error);
}

TEST(RelightOpenHemisphere, IsTheConstantOne) {
  const sh::ShCoeffs v = open_visibility();
  for (const sh::Vec3& d : {sh::Vec3{0, 0, 1}, sh::Vec3{1, 0, 0}, sh::Vec3{0, -0.6, 0.8}}) {
    const sh::ShCoeffs y = sh::sh_basis(d);
    double sum = 0;
    for (int i = 0; i < 9; ++i) sum += v[i] * y[i];
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
}

TEST(RelightMode, NamesAndErrors) {
  EXPECT_EQ(mode_from_name("ratio"), Mode::Ratio);
  EXPECT_EQ(mode_from_name("render"), Mode::Render);
  EXPECT_THROW(mode_from_name("divide"), Error);
}

}  // namespace
}  // namespace facetool::relight
