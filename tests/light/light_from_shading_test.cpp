// The light from a face's shading (libs/light/light_from_shading.h) on synthetic faces rendered
// through the renderer's SH model under a known distant light plus ambient: the direction within
// 3 degrees and |L1|/L0 within 10 %, with cast shadows, highlights, dark albedo features, shading
// baked into the albedo given, a grey photo; a face lit from behind stays finite and is warned of.
// Also the albedo that follows (libs/inference/albedo_from_shading.h) and the direction light.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/sh/pixel_transfer.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sphere_samples.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"
#include "libs/inference/albedo_from_shading.h"
#include "libs/light/direction_light.h"
#include "libs/light/light_from_shading.h"

namespace facetool {
namespace {

constexpr int kSize = 96;
constexpr size_t kPlane = static_cast<size_t>(kSize) * kSize;

sh::Vec3 unit(double x, double y, double z) {
  const double n = std::sqrt(x * x + y * y + z * z);
  return {x / n, y / n, z / n};
}

double angle_deg(const sh::Vec3& a, const sh::Vec3& b) {
  return std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0)) * 180.0 / kPi;
}

// |L1| / L0 of the colours' mean light: sqrt(3) for one distant light alone.
double directionality(const sh::RgbLight& l) {
  double l0 = 0, l1[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    l0 += l[c * 9] / 3;
    for (int i = 0; i < 3; ++i) l1[i] += l[c * 9 + 1 + i] / 3;
  }
  return std::sqrt(l1[0] * l1[0] + l1[1] * l1[1] + l1[2] * l1[2]) / l0;
}

// A face-like crop: an ellipsoid filling the middle (normals), the open hemisphere above each
// normal as its visibility, or with `cast_shadow` the left third also blocked towards +X (as if a
// nose stood to its right), by quadrature over 872 directions; the skin albedo with dark brows and
// lips when `features`.
struct SyntheticFace {
  std::vector<float> normal = std::vector<float>(3 * kPlane, 0.0f);
  std::vector<float> visibility = std::vector<float>(9 * kPlane, 0.0f);
  std::vector<float> albedo = std::vector<float>(3 * kPlane, 0.0f);
  std::vector<float> mask = std::vector<float>(kPlane, 0.0f);
  std::vector<uint8_t> shadowed = std::vector<uint8_t>(kPlane, 0);
};

SyntheticFace make_face(bool cast_shadow, bool features) {
  SyntheticFace f;
  const std::vector<sh::Vec3> dirs = sh::fibonacci_sphere(sh::kVisibilitySampleCount);
  const double skin[3] = {0.62, 0.46, 0.38};
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const size_t p = static_cast<size_t>(y) * kSize + x;
      const double u = (x + 0.5 - kSize / 2.0) / 34.0, v = -(y + 0.5 - kSize / 2.0) / 42.0;
      const double r2 = u * u + v * v;
      if (r2 >= 0.97) continue;
      const sh::Vec3 n = unit(u / 34.0, v / 42.0, std::sqrt(1 - r2) / 20.0);  // gradient of the ellipsoid
      for (int k = 0; k < 3; ++k) f.normal[k * kPlane + p] = static_cast<float>(n[k]);
      f.mask[p] = 1.0f;
      const bool blocked = cast_shadow && u < -0.25 && u > -0.85;
      f.shadowed[p] = blocked;
      double vis[9] = {0};
      for (const sh::Vec3& w : dirs) {
        if (w[0] * n[0] + w[1] * n[1] + w[2] * n[2] <= 0) continue;
        if (blocked && w[0] > 0.15) continue;
        double y9[9];
        sh::sh_basis(w[0], w[1], w[2], y9);
        for (int j = 0; j < 9; ++j) vis[j] += y9[j];
      }
      for (int j = 0; j < 9; ++j) f.visibility[j * kPlane + p] = static_cast<float>(vis[j] * 4 * kPi / dirs.size());
      const bool brow = std::abs(v - 0.35) < 0.06 && std::abs(u) > 0.12 && std::abs(u) < 0.55;
      const bool lips = std::abs(v + 0.5) < 0.07 && std::abs(u) < 0.3;
      for (int c = 0; c < 3; ++c)
        f.albedo[c * kPlane + p] = static_cast<float>(features && (brow || lips) ? 0.25 * skin[c] : skin[c]);
    }
  return f;
}

// The renderer's image of the face under `light`: albedo / pi * sum_i L_ci transfer_i.
std::vector<float> render(const SyntheticFace& f, const std::vector<float>& albedo, const sh::RgbLight& light,
                          std::vector<float>* shading = nullptr) {
  std::vector<float> image(3 * kPlane, 0.0f);
  if (shading) shading->assign(3 * kPlane, 0.0f);
  for (size_t p = 0; p < kPlane; ++p) {
    if (f.mask[p] <= 0.5f) continue;
    sh::ShCoeffs v;
    for (int j = 0; j < 9; ++j) v[j] = f.visibility[j * kPlane + p];
    const sh::ShCoeffs t = pixel_transfer({f.normal[p], f.normal[kPlane + p], f.normal[2 * kPlane + p]}, v);
    for (int c = 0; c < 3; ++c) {
      double s = 0;
      for (int i = 0; i < 9; ++i) s += light[c * 9 + i] * t[i] / kPi;
      image[c * kPlane + p] = static_cast<float>(albedo[c * kPlane + p] * s);
      if (shading) (*shading)[c * kPlane + p] = static_cast<float>(s);
    }
  }
  return image;
}

DistantLight truth_light(const sh::Vec3& d, double ambient, double intensity) {
  DistantLight l;
  l.direction = d;
  l.ambient = {ambient, ambient * 0.95, ambient * 0.9};
  l.intensity = {intensity, intensity * 0.97, intensity * 0.9};
  return l;
}

DistantLight solve(const SyntheticFace& f, const std::vector<float>& image, const std::vector<float>& albedo) {
  ShadingInputs in;
  in.image = image.data();
  in.albedo = albedo.data();
  in.normal = f.normal.data();
  in.visibility = f.visibility.data();
  in.mask = f.mask.data();
  in.size = kSize;
  return solve_distant_light(in);
}

void expect_recovered(const DistantLight& truth, const DistantLight& found, const char* what) {
  ASSERT_TRUE(found.solved) << what;
  EXPECT_LT(angle_deg(truth.direction, found.direction), 3.0)
      << what << ": found (" << found.direction[0] << ", " << found.direction[1] << ", " << found.direction[2]
      << "), truth (" << truth.direction[0] << ", " << truth.direction[1] << ", " << truth.direction[2] << ")";
  const double want = directionality(sh_light(truth)), got = directionality(sh_light(found));
  EXPECT_NEAR(got, want, 0.1 * want) << what;
  for (double v : sh_light(found)) EXPECT_TRUE(std::isfinite(v)) << what;
}

const sh::Vec3 kSide = unit(0.75, 0.2, 0.63);  // 50 degrees to the viewer's right, a little above

TEST(SolveDistantLight, RecoversASideLightOnAPlainFace) {
  const SyntheticFace f = make_face(false, false);
  const DistantLight truth = truth_light(kSide, 0.08, 2.5);
  expect_recovered(truth, solve(f, render(f, f.albedo, sh_light(truth)), f.albedo), "plain");
}

TEST(SolveDistantLight, RecoversLightsFromAboveAndNearTheCamera) {
  const SyntheticFace f = make_face(false, true);
  for (const sh::Vec3& d : {unit(0, 0.7, 0.71), unit(-0.3, -0.1, 0.95), unit(-0.94, 0, 0.34)}) {
    const DistantLight truth = truth_light(d, 0.05, 2.0);
    expect_recovered(truth, solve(f, render(f, f.albedo, sh_light(truth)), f.albedo), "direction");
  }
}

TEST(SolveDistantLight, UsesTheVisibilityWhereAThirdOfTheFaceIsInCastShadow) {
  const SyntheticFace f = make_face(true, false);
  size_t shadowed = 0, face = 0;
  for (size_t p = 0; p < kPlane; ++p) {
    shadowed += f.shadowed[p];
    face += f.mask[p] > 0.5f;
  }
  ASSERT_GT(shadowed * 4, face) << "the cast shadow covers too little of the face to test anything";
  const DistantLight truth = truth_light(kSide, 0.06, 2.5);
  expect_recovered(truth, solve(f, render(f, f.albedo, sh_light(truth)), f.albedo), "cast shadow");
}

TEST(SolveDistantLight, IgnoresSpecularHighlights) {
  const SyntheticFace f = make_face(false, false);
  const DistantLight truth = truth_light(kSide, 0.08, 2.5);
  std::vector<float> image = render(f, f.albedo, sh_light(truth));
  // A saturated highlight and a bright halo around it where the half vector meets the normal.
  const sh::Vec3 h = unit(kSide[0], kSide[1], kSide[2] + 1);
  size_t spots = 0;
  for (size_t p = 0; p < kPlane; ++p) {
    if (f.mask[p] <= 0.5f) continue;
    const double c = f.normal[p] * h[0] + f.normal[kPlane + p] * h[1] + f.normal[2 * kPlane + p] * h[2];
    if (c < 0.97) continue;
    ++spots;
    for (int ch = 0; ch < 3; ++ch) image[ch * kPlane + p] = c > 0.99 ? 1.0f : std::min(0.94f, image[ch * kPlane + p] + 0.4f);
  }
  ASSERT_GT(spots, 30u);
  expect_recovered(truth, solve(f, image, f.albedo), "highlights");
}

TEST(SolveDistantLight, DarkAlbedoFeaturesAndShadingBakedIntoTheAlbedoGiven) {
  const SyntheticFace f = make_face(false, true);
  const DistantLight truth = truth_light(kSide, 0.08, 2.5);
  const std::vector<float> image = render(f, f.albedo, sh_light(truth));
  expect_recovered(truth, solve(f, image, f.albedo), "features, true albedo");
  // The network's albedo keeps some of the photo's smooth shading: the light must still be found.
  std::vector<float> shading;
  render(f, f.albedo, sh_light(truth), &shading);
  std::vector<float> baked = f.albedo;
  for (size_t p = 0; p < kPlane; ++p)
    for (int c = 0; c < 3; ++c) baked[c * kPlane + p] *= 0.6f + 0.4f * std::min(1.0f, shading[c * kPlane + p]);
  expect_recovered(truth, solve(f, image, baked), "features, shading in the albedo");
}

TEST(SolveDistantLight, GreyPhotoGetsAGreyLight) {
  const SyntheticFace f = make_face(false, true);
  DistantLight truth = truth_light(kSide, 0.08, 2.5);
  truth.ambient = {0.08, 0.08, 0.08};
  truth.intensity = {2.5, 2.5, 2.5};
  std::vector<float> image = render(f, f.albedo, sh_light(truth));
  for (size_t p = 0; p < kPlane; ++p) {
    const float g = (image[p] + image[kPlane + p] + image[2 * kPlane + p]) / 3;
    for (int c = 0; c < 3; ++c) image[c * kPlane + p] = g;
  }
  const DistantLight found = solve(f, image, f.albedo);
  expect_recovered(truth, found, "grey");
  EXPECT_EQ(found.intensity[0], found.intensity[2]);
  EXPECT_EQ(found.ambient[0], found.ambient[1]);
}

TEST(SolveDistantLight, ALightFromBehindIsFiniteAndWarnedOf) {
  const SyntheticFace f = make_face(false, false);
  for (const sh::Vec3& d : {unit(0.98, 0.1, -0.17), unit(-0.7, 0.1, -0.7)}) {
    const DistantLight truth = truth_light(d, 0.01, 2.5);
    std::vector<float> image = render(f, f.albedo, sh_light(truth));
    for (float& v : image) v = std::max(v, 0.0f);  // a camera records no negative light
    const DistantLight found = solve(f, image, f.albedo);
    EXPECT_FALSE(found.warning.empty()) << found.solved << " " << found.pixels << " (" << found.direction[0] << ", "
                                        << found.direction[1] << ", " << found.direction[2] << ") "
                                        << found.relative_residual;
    for (double v : sh_light(found)) EXPECT_TRUE(std::isfinite(v));
    for (double v : found.direction) EXPECT_TRUE(std::isfinite(v));
  }
}

TEST(SolveDistantLight, TooFewPixelsLeavesTheLightUnsolved) {
  SyntheticFace f = make_face(false, false);
  const std::vector<float> image = render(f, f.albedo, sh_light(truth_light(kSide, 0.1, 2)));
  std::fill(f.mask.begin(), f.mask.end(), 0.0f);
  for (size_t p = 0; p < kMinLightSolvePixels - 1; ++p) f.mask[kPlane / 2 + p] = 1.0f;
  EXPECT_FALSE(solve(f, image, f.albedo).solved);
}

TEST(AlbedoFromShading, IsThePhotoOverTheShadingWhereLitAndTheNetworksInTheDark) {
  const SyntheticFace f = make_face(false, true);
  const DistantLight truth = truth_light(kSide, 0.0, 2.5);
  std::vector<float> shading;
  const std::vector<float> image = render(f, f.albedo, sh_light(truth), &shading);
  std::vector<float> network = f.albedo;
  for (float& a : network) a *= 0.7f;  // the network's albedo, too dark
  std::vector<float> albedo = network;
  albedo_from_shading(image.data(), shading.data(), f.mask.data(), kPlane, albedo.data());
  std::vector<float> face_shading;
  for (size_t p = 0; p < kPlane; ++p)
    if (f.mask[p] > 0.5f) face_shading.push_back((shading[p] + shading[kPlane + p] + shading[2 * kPlane + p]) / 3);
  std::nth_element(face_shading.begin(), face_shading.begin() + face_shading.size() / 2, face_shading.end());
  const float median = face_shading[face_shading.size() / 2];
  size_t lit = 0, dark = 0;
  for (size_t p = 0; p < kPlane; ++p) {
    if (f.mask[p] <= 0.5f) continue;
    const float s = (shading[p] + shading[kPlane + p] + shading[2 * kPlane + p]) / 3;
    for (int c = 0; c < 3; ++c) {
      if (s >= kLitShading * median) {
        EXPECT_NEAR(albedo[c * kPlane + p], f.albedo[c * kPlane + p], 1e-4f) << p;
        lit += c == 0;
      } else if (s <= kDarkShading * median) {
        EXPECT_EQ(albedo[c * kPlane + p], network[c * kPlane + p]) << p;
        dark += c == 0;
      }
    }
  }
  EXPECT_GT(lit, 1000u);
  EXPECT_GT(dark, 100u);
}

TEST(DirectionLight, ShadesAmbientPlusIntensityTimesTheCosine) {
  // Azimuth +40 turns the light to the viewer's right (+X), elevation +20 upwards.
  const sh::Vec3 d = light::direction_from_angles(40, 20);
  EXPECT_NEAR(d[0], std::sin(40 * kPi / 180) * std::cos(20 * kPi / 180), 1e-12);
  EXPECT_GT(d[0], 0);
  EXPECT_GT(d[1], 0);
  const sh::RgbLight l = light::light_from_direction(40, 20, 0.2, 1.5);
  // Facing the light, nothing occluded (v = 1: v_0 = sqrt(4 pi)): 0.2 + 1.5 x the 9 coefficients'
  // 1.0625 of the cosine (1/4 + 1/2 + 5/16 from the three bands); at 90 degrees to it the ambient
  // plus the band-2 ring, 1.5 x (1/4 - 5/32).
  sh::ShCoeffs open{};
  open[0] = std::sqrt(4 * kPi);
  const sh::Vec3 side = unit(-d[2], 0, d[0]);
  for (int c = 0; c < 3; ++c) {
    double facing = 0, across = 0;
    const sh::ShCoeffs t = pixel_transfer(d, open), u = pixel_transfer(side, open);
    for (int i = 0; i < 9; ++i) {
      facing += l[c * 9 + i] * t[i] / kPi;
      across += l[c * 9 + i] * u[i] / kPi;
    }
    EXPECT_NEAR(facing, 0.2 + 1.5 * 1.0625, 1e-9) << c;
    EXPECT_NEAR(across, 0.2 + 1.5 * (0.25 - 5.0 / 32), 1e-9) << c;
  }
  EXPECT_THROW(light::light_from_direction(std::nan(""), 0, 0.1, 1), Error);
  EXPECT_THROW(light::light_from_direction(0, 0, -0.1, 1), Error);
}

}  // namespace
}  // namespace facetool
