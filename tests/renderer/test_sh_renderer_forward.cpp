// Forward tests of the sh_renderer: quadrature, Ramamoorthi-Hanrahan irradiance, masks, errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/backend/registry.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sh_eval.h"
#include "core/util/error.h"
#include "render_fixture.h"
#include "sphere_quadrature.h"
#include "tests/support/test_support.h"
#include "core/util/math_constants.h"

namespace facetool::testing {
namespace {


sh::Vec3 unit(const sh::Vec3& n) {
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  return {n[0] / len, n[1] / len, n[2] / len};
}

// I = rho / pi * integral of L~ v~ c~ over the sphere, where ~ are the degree <= 2 projections;
// c~'s coefficients themselves come from quadrature of max(0, w.n) Y_k (kink on the split).
TEST(ShRendererForward, MatchesBruteForceQuadrature) {
  const HostScene s = random_scene(2, 3, 4, 1);
  RenderOutputs out;
  sh_renderer().forward(upload(get_backend("cpu"), s), out);
  const std::vector<float> image = out.image.to_host(), shading = out.shading.to_host();
  const int64_t pixels = s.h * s.w;
  for (int64_t b = 0; b < s.n; ++b)
    for (int64_t p = 0; p < pixels; ++p) {
      const sh::Vec3 n = unit(pixel_normal(s, b, p));
      sh::ShCoeffs c{};
      for (int k = 0; k < 9; ++k)
        c[k] = integrate_sphere(
            [&](const sh::Vec3& w) {
              return std::fmax(0.0, w[0] * n[0] + w[1] * n[1] + w[2] * n[2]) * sh::sh_basis(w)[k];
            },
            8, 16, n);
      const sh::ShCoeffs v = pixel_visibility(s, b, p);
      for (int ch = 0; ch < 3; ++ch) {
        const sh::ShCoeffs l = image_light(s, b, ch);
        const double integral = integrate_sphere(
            [&](const sh::Vec3& w) { return sh::sh_eval(l, w) * sh::sh_eval(v, w) * sh::sh_eval(c, w); },
            8, 16);
        const int64_t at = (b * 3 + ch) * pixels + p;
        const double expected_shading = integral / kPi;
        const double scale = std::fabs(expected_shading) + 0.1;
        EXPECT_NEAR(shading[at], expected_shading, 1e-4 * scale) << "image " << b << " pixel " << p;
        EXPECT_NEAR(image[at], s.albedo[at] * expected_shading, 1e-4 * scale);
      }
    }
}

// With v = 1 (v_0 = 2 sqrt(pi)) the renderer gives rho / pi * E(n), E the irradiance of
// Ramamoorthi & Hanrahan (2001), eq. 13, written with their constants c1..c5.
TEST(ShRendererForward, UnitVisibilityGivesRamamoorthiHanrahanIrradiance) {
  const double c1 = kPi / 4.0 * std::sqrt(15.0 / kPi) / 4.0;  // A_2 times Y_2^2's constant
  const double c2 = kPi / 3.0 * std::sqrt(3.0 / (4.0 * kPi));  // half of A_1 * Y_1 constant
  const double c3 = kPi / 4.0 * 3.0 * std::sqrt(5.0 / kPi) / 4.0;
  const double c4 = kPi / (2.0 * std::sqrt(kPi));
  const double c5 = kPi / 4.0 * std::sqrt(5.0 / kPi) / 4.0;
  // The values printed in their paper (rounded to 6 digits; 0.743125 is 0.7431239 rounded up).
  EXPECT_NEAR(c1, 0.429043, 1e-6);
  EXPECT_NEAR(c2, 0.511664, 1e-6);
  EXPECT_NEAR(c3, 0.743125, 2e-6);
  EXPECT_NEAR(c4, 0.886227, 1e-6);
  EXPECT_NEAR(c5, 0.247708, 1e-6);

  HostScene s = random_scene(2, 4, 5, 2);
  const int64_t pixels = s.h * s.w;
  for (int64_t b = 0; b < s.n; ++b)
    for (int64_t p = 0; p < pixels; ++p)
      for (int j = 0; j < 9; ++j)
        s.visibility[(b * 9 + j) * pixels + p] = j == 0 ? static_cast<float>(2.0 * std::sqrt(kPi)) : 0.0f;
  RenderOutputs out;
  sh_renderer().forward(upload(get_backend("cpu"), s), out);
  const std::vector<float> image = out.image.to_host();
  for (int64_t b = 0; b < s.n; ++b)
    for (int64_t p = 0; p < pixels; ++p) {
      const sh::Vec3 n = unit(pixel_normal(s, b, p));
      const double x = n[0], y = n[1], z = n[2];
      for (int ch = 0; ch < 3; ++ch) {
        const sh::ShCoeffs L = image_light(s, b, ch);
        // L[0]=L00, L[1]=L1-1, L[2]=L10, L[3]=L11, L[4]=L2-2, L[5]=L2-1, L[6]=L20, L[7]=L21, L[8]=L22
        const double e = c1 * L[8] * (x * x - y * y) + c3 * L[6] * z * z + c4 * L[0] - c5 * L[6] +
                         2.0 * c1 * (L[4] * x * y + L[7] * x * z + L[5] * y * z) +
                         2.0 * c2 * (L[3] * x + L[1] * y + L[2] * z);
        const int64_t at = (b * 3 + ch) * pixels + p;
        const double expected = s.albedo[at] / kPi * e;
        EXPECT_NEAR(image[at], expected, 1e-5 * (std::fabs(expected) + 0.1));
      }
    }
}

TEST(ShRendererForward, MaskAndZeroNormalsGiveZero) {
  HostScene s = random_scene(1, 3, 3, 3);
  const int64_t pixels = 9;
  RenderOutputs full;
  sh_renderer().forward(upload(get_backend("cpu"), s), full);
  s.mask.assign(pixels, 1.0f);
  s.mask[2] = 0.0f;
  s.mask[5] = 0.2f;  // below 0.5: outside
  for (int a = 0; a < 3; ++a) s.normal[a * pixels + 7] = 0.0f;                          // zero length
  s.normal[2 * pixels + 2] = std::numeric_limits<float>::quiet_NaN();  // NaN, but masked out
  RenderOutputs masked;
  sh_renderer().forward(upload(get_backend("cpu"), s), masked);
  const std::vector<float> a = full.image.to_host(), m = masked.image.to_host(),
                           sh = masked.shading.to_host();
  for (int ch = 0; ch < 3; ++ch)
    for (int64_t p = 0; p < pixels; ++p) {
      const int64_t at = ch * pixels + p;
      if (p == 2 || p == 5 || p == 7) {
        EXPECT_EQ(m[at], 0.0f);
        EXPECT_EQ(sh[at], 0.0f);
      } else {
        EXPECT_EQ(m[at], a[at]);
      }
    }
}

TEST(ShRendererForward, BadInputsAreErrors) {
  Backend& cpu = get_backend("cpu");
  const HostScene s = random_scene(1, 2, 2, 4);
  RendererPlugin& r = sh_renderer();
  auto expect_error = [&](RenderInputs in, const char* what) {
    RenderOutputs out;
    EXPECT_THROW(r.forward(in, out), Error) << what;
  };
  RenderInputs in = upload(cpu, s);
  RenderInputs bad = in;
  bad.albedo = Tensor::zeros(cpu, Shape{1, 4, 2, 2});
  expect_error(bad, "albedo with 4 channels");
  bad = in;
  bad.normal = Tensor::zeros(cpu, Shape{1, 2, 2, 2});
  expect_error(bad, "normal with 2 channels");
  bad = in;
  bad.visibility = Tensor::zeros(cpu, Shape{1, 8, 2, 2});
  expect_error(bad, "visibility with 8 channels");
  bad = in;
  bad.light = Tensor::zeros(cpu, Shape{1, 26});
  expect_error(bad, "light with 26 values");
  bad = in;
  bad.mask = Tensor::zeros(cpu, Shape{1, 2, 2, 2});
  expect_error(bad, "mask with 2 channels");
  bad = in;
  bad.visibility = Tensor::zeros(cpu, Shape{1, 9, 2, 3});
  expect_error(bad, "visibility of another size");
  bad = in;
  bad.light = Tensor();
  expect_error(bad, "missing light");

  HostScene nan_normal = s;
  nan_normal.normal[1] = std::numeric_limits<float>::quiet_NaN();
  expect_error(upload(cpu, nan_normal), "NaN normal");
  HostScene inf_normal = s;
  inf_normal.normal[0] = std::numeric_limits<float>::infinity();
  expect_error(upload(cpu, inf_normal), "infinite normal");
  HostScene nan_light = s;
  nan_light.light[5] = std::numeric_limits<float>::quiet_NaN();
  expect_error(upload(cpu, nan_light), "NaN light");
  try {
    RenderOutputs out;
    r.forward(upload(cpu, nan_normal), out);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("normal"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace facetool::testing
