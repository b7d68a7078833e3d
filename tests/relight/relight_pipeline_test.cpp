// The relighting pipeline on a synthetic sphere with known normals, visibility and lights: own light
// returns the photo / the reconstruction, full turns return the image, half turns move the bright
// side, and the transferred shading matches the closed-form irradiance of the new light.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "libs/photo/relight_pipeline.h"
#include "core/backend/registry.h"
#include "core/plugin/plugin_loader.h"
#include "core/sh/clamped_cosine.h"
#include "core/sh/sh_basis.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {

constexpr int kSize = 64;

RendererPlugin& sh_renderer() {
  static PluginLoader loader;
  static std::shared_ptr<Plugin> object = [] {
    const PluginInfo& info = loader.load_file(FACETOOL_SH_RENDERER_PLUGIN);
    check(info.kind == FACETOOL_PLUGIN_RENDERER, "sh_renderer is not a renderer plugin");
    return loader.create(info);
  }();
  return *dynamic_cast<RendererPlugin*>(object.get());
}

sh::Vec3 sphere_normal(int x, int y) {
  const double nx = (x + 0.5 - kSize / 2.0) / (kSize / 2.0), ny = -(y + 0.5 - kSize / 2.0) / (kSize / 2.0);
  const double r2 = nx * nx + ny * ny;
  if (r2 >= 1) return {0, 0, 1};
  return {nx, ny, std::sqrt(1 - r2)};
}

// A one-sided light: each channel is `scale` times the clamped cosine about `direction`.
sh::RgbLight one_sided_light(const sh::Vec3& direction, const sh::Vec3& scale) {
  const sh::ShCoeffs c = sh::clamped_cosine_coeffs(direction);
  sh::RgbLight light{};
  for (int ch = 0; ch < 3; ++ch)
    for (int i = 0; i < 9; ++i) light[ch * 9 + i] = scale[ch] * c[i];
  return light;
}

// The renderer's shading with an unoccluded pixel, written from its definition:
// 1/pi * integral L(w) max(0, w.n) dw = 1/pi * sum_i A_l L_i Y_i(n).
double closed_form_shading(const sh::RgbLight& light, int channel, const sh::Vec3& n) {
  const sh::ShCoeffs y = sh::sh_basis(n);
  double sum = 0;
  for (int i = 0; i < 9; ++i) sum += sh::cosine_band_factor(sh::sh_band(i)) * light[channel * 9 + i] * y[i];
  return sum / kPi;
}

// A sphere "photo" decomposed as the network would: one face whose crop is the sphere, with
// visibility `v0` (constant, SH ambient coefficient) and light `own`; the photo is a texture
// unrelated to albedo x shading, so the ratio mode must carry it through.
DecomposedPhoto sphere_photo(const sh::RgbLight& own, double v0, const Similarity2& photo_to_crop, int photo_size) {
  const size_t plane = static_cast<size_t>(kSize) * kSize;
  Decomposition d;
  d.count = 1;
  d.size = kSize;
  d.albedo.resize(3 * plane);
  d.normal.resize(3 * plane);
  d.visibility.assign(9 * plane, 0.0f);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t p = static_cast<size_t>(y) * kSize + x;
      const sh::Vec3 n = sphere_normal(x, y);
      for (int c = 0; c < 3; ++c) {
        d.normal[c * plane + p] = static_cast<float>(n[c]);
        d.albedo[c * plane + p] = static_cast<float>(0.4 + 0.3 * std::sin(0.3 * x + 0.2 * y + c));
      }
      d.visibility[p] = static_cast<float>(v0);
    }
  d.light.assign(own.begin(), own.end());
  Backend& cpu = get_backend("cpu");
  RenderInputs in{Tensor::from_host(cpu, Shape{1, 3, kSize, kSize}, d.albedo),
                  Tensor::from_host(cpu, Shape{1, 3, kSize, kSize}, d.normal),
                  Tensor::from_host(cpu, Shape{1, 9, kSize, kSize}, d.visibility),
                  Tensor::from_host(cpu, Shape{1, 27}, d.light), Tensor()};
  RenderOutputs out;
  sh_renderer().forward(in, out);
  d.shading = out.shading.to_host();
  d.reconstruction = out.image.to_host();

  FaceCrop crop;
  crop.alignment.crop_size = kSize;
  crop.alignment.photo_to_crop = photo_to_crop;
  for (int k = 0; k < 64; ++k) {  // the mask: a circle just inside the sphere's outline
    const double a = 2 * kPi * k / 64;
    crop.mask_polygon.push_back({kSize / 2.0 + 0.45 * kSize * std::cos(a), kSize / 2.0 + 0.45 * kSize * std::sin(a)});
  }
  RgbImage photo;
  photo.width = photo.height = photo_size;
  photo.pixels.resize(static_cast<size_t>(photo_size) * photo_size * 3);
  for (size_t i = 0; i < photo.pixels.size(); ++i) photo.pixels[i] = static_cast<float>(0.5 + 0.4 * std::sin(0.017 * i));
  return assemble_decomposed_photo("sphere", photo, {crop}, d, 2.0);
}

const sh::RgbLight kOwnLight = [] {
  sh::RgbLight l = one_sided_light({0.3, 0.4, 0.866}, {2.0, 1.8, 1.6});
  l[0] += 0.5, l[9] += 0.5, l[18] += 0.5;  // some ambient light
  return l;
}();

RelitPhoto relight(const DecomposedPhoto& p, const sh::RgbLight& light, relight::Mode mode, bool visibility = true) {
  RelightSettings s;
  s.mode = mode;
  s.visibility = visibility;
  return relight_photo(p, light, s, sh_renderer(), get_backend("cpu"));
}

TEST(RelightPipeline, RatioWithOwnLightReturnsThePhoto) {
  const DecomposedPhoto p = sphere_photo(kOwnLight, 2 * std::sqrt(kPi) * 0.7, Similarity2{}, kSize);
  const RelitPhoto r = relight(p, p.photo_lights[0], relight::Mode::Ratio);
  for (size_t i = 0; i < r.image.pixels.size(); ++i) ASSERT_NEAR(r.image.pixels[i], p.photo.pixels[i], 1e-5f) << i;
}

TEST(RelightPipeline, RatioWithOwnLightReturnsThePhotoThroughATurnedAlignment) {
  // The face sits turned by 30 degrees and scaled in a larger photo: the light goes crop ->
  // photo frame -> crop; a wrong turn would change the shading and so the photo.
  const Similarity2 t = Similarity2::from(0.6, 30 * kPi / 180, -10, 12);
  const DecomposedPhoto p = sphere_photo(kOwnLight, 2 * std::sqrt(kPi), t, 110);
  double covered = 0;
  for (float a : p.layers.alpha) covered += a;
  ASSERT_GT(covered, 1000) << "the sphere must land in the photo";
  const RelitPhoto r = relight(p, p.photo_lights[0], relight::Mode::Ratio);
  for (size_t i = 0; i < r.image.pixels.size(); ++i) ASSERT_NEAR(r.image.pixels[i], p.photo.pixels[i], 1e-5f) << i;
  // ... while another light does change it inside the face.
  const RelitPhoto other = relight(p, relight::orbit_light(p.photo_lights[0], 1, 4), relight::Mode::Ratio);
  double change = 0;
  for (size_t i = 0; i < other.image.pixels.size(); ++i) change += std::abs(other.image.pixels[i] - p.photo.pixels[i]);
  EXPECT_GT(change / covered, 0.05);
}

TEST(RelightPipeline, RenderWithOwnLightReturnsTheReconstruction) {
  const DecomposedPhoto p = sphere_photo(kOwnLight, 2 * std::sqrt(kPi) * 0.8, Similarity2{}, kSize);
  const RelitPhoto r = relight(p, p.photo_lights[0], relight::Mode::Render);
  const size_t plane = static_cast<size_t>(kSize) * kSize;
  int inside = 0;
  for (size_t q = 0; q < plane; ++q) {
    if (p.layers.alpha[q] < 1.0f) continue;
    ++inside;
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(r.image.pixels[q * 3 + c], p.decomposition.reconstruction[c * plane + q], 1e-5f) << q;
  }
  EXPECT_GT(inside, 2000);
}

TEST(RelightPipeline, FullTurnReturnsTheImage) {
  const DecomposedPhoto p = sphere_photo(kOwnLight, 2 * std::sqrt(kPi), Similarity2{}, kSize);
  const sh::RgbLight light = one_sided_light({0.8, 0.0, 0.6}, {1.5, 1.0, 0.7});
  const RelitPhoto a = relight(p, light, relight::Mode::Render);
  const RelitPhoto b = relight(p, relight::orbit_light(light, 36, 36), relight::Mode::Render);
  for (size_t i = 0; i < a.image.pixels.size(); ++i) ASSERT_NEAR(a.image.pixels[i], b.image.pixels[i], 1e-5f) << i;
}

TEST(RelightPipeline, HalfTurnMovesTheBrightSideAcross) {
  const DecomposedPhoto p = sphere_photo(kOwnLight, 2 * std::sqrt(kPi), Similarity2{}, kSize);
  const sh::RgbLight right = one_sided_light({1, 0, 0}, {1, 1, 1});  // lit from the viewer's right
  const RelitPhoto before = relight(p, right, relight::Mode::Render);
  const RelitPhoto after = relight(p, relight::orbit_light(right, 1, 2), relight::Mode::Render);
  auto side_means = [&](const RelitPhoto& r) {
    double left = 0, right_sum = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const size_t q = static_cast<size_t>(y) * kSize + x;
        if (p.layers.alpha[q] < 1.0f) continue;
        (x < kSize / 2 ? left : right_sum) += r.new_shading[q];
      }
    return std::pair<double, double>{left, right_sum};
  };
  const auto [l0, r0] = side_means(before);
  const auto [l1, r1] = side_means(after);
  EXPECT_GT(r0, 2 * l0);  // degree-2 SH of a one-sided light still lights the far side a little
  EXPECT_GT(l1, 2 * r1);
  // This light depends on w.x only, so the turned shading is the mirror image in x.
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t q = static_cast<size_t>(y) * kSize + x, m = static_cast<size_t>(y) * kSize + (kSize - 1 - x);
      if (p.layers.alpha[q] < 1.0f || p.layers.alpha[m] < 1.0f) continue;
      ASSERT_NEAR(after.new_shading[q], before.new_shading[m], 1e-4f) << x << "," << y;
    }
}

TEST(RelightPipeline, TransferredShadingMatchesTheClosedFormIrradiance) {
  // Unoccluded sphere: the new shading must be 1/pi sum A_l L_i Y_i(n) for the transferred light
  // (a coloured light from a synthetic sample, unrelated to the photo's own).
  const DecomposedPhoto p = sphere_photo(kOwnLight, 2 * std::sqrt(kPi), Similarity2{}, kSize);
  sh::RgbLight light = one_sided_light({-0.5, 0.5, 0.707}, {1.2, 0.9, 2.0});
  light[0] += 0.3, light[9] += 0.2, light[18] += 0.1, light[4 + 9] += 0.15;
  const RelitPhoto r = relight(p, light, relight::Mode::Render);
  const size_t plane = static_cast<size_t>(kSize) * kSize;
  double worst = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t q = static_cast<size_t>(y) * kSize + x;
      if (p.layers.alpha[q] < 1.0f) continue;
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(r.new_shading[c * plane + q] - closed_form_shading(light, c, sphere_normal(x, y))));
    }
  EXPECT_LT(worst, 1e-4);
}

TEST(RelightPipeline, NoVisibilityUsesTheOpenHemisphere) {
  // Visibility 0.5 everywhere (half the sphere of directions blocked on average): the open
  // hemisphere's shading is twice the occluded one for the same light.
  const DecomposedPhoto p = sphere_photo(kOwnLight, 0.5 * 2 * std::sqrt(kPi), Similarity2{}, kSize);
  const RelitPhoto with = relight(p, kOwnLight, relight::Mode::Render, true);
  const RelitPhoto open = relight(p, kOwnLight, relight::Mode::Render, false);
  const size_t plane = static_cast<size_t>(kSize) * kSize;
  for (size_t q = 0; q < plane; ++q) {
    if (p.layers.alpha[q] < 1.0f) continue;
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(open.new_shading[c * plane + q], 2 * with.new_shading[c * plane + q], 1e-4f) << q;
  }
}

}  // namespace
}  // namespace facetool
