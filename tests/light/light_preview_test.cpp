// The light preview against independent evaluations: each sphere pixel well inside shows
// (1 / pi) * integral of max(0, n . w) L(w) (quadrature), each panorama pixel L at its direction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

#include "libs/light/light_preview.h"
#include "core/sh/envmap_projection.h"
#include "core/sh/sh_eval.h"
#include "core/sh/sphere_samples.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace {

TEST(LightPreview, SphereShowsTheIrradianceOfTheLight) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  sh::RgbLight light;
  for (double& v : light) v = u(rng);
  for (int c = 0; c < 3; ++c) light[c * 9] = 2.0 + 0.3 * c;  // positive everywhere
  const int size = 48;
  const light::LightPreview preview = light::render_light_preview(light, size);
  ASSERT_EQ(preview.image.width, 3 * size);
  ASSERT_FALSE(preview.negative_shading);

  const std::vector<sh::Vec3> directions = sh::fibonacci_sphere(sh::kIlluminationSampleCount);
  std::vector<double> radiance[3];
  for (const sh::Vec3& w : directions) {
    const std::array<double, 3> l = sh::light_eval(light, w);
    for (int c = 0; c < 3; ++c) radiance[c].push_back(l[c]);
  }
  const double solid_angle = 4.0 * kPi / directions.size();
  const double radius = 0.5 * size * 0.94, centre = 0.5 * size;  // the header's sphere
  int checked = 0;
  double worst = 0;
  for (int row = 0; row < size; row += 3)
    for (int col = 0; col < size; col += 3) {
      const double x = (col + 0.5 - centre) / radius, y = -(row + 0.5 - centre) / radius;
      if (x * x + y * y > 0.7 * 0.7) continue;  // well inside: the normal varies slowly
      const sh::Vec3 n{x, y, std::sqrt(1.0 - x * x - y * y)};
      for (int c = 0; c < 3; ++c) {
        double irradiance = 0;
        for (size_t k = 0; k < directions.size(); ++k) {
          const sh::Vec3& w = directions[k];
          irradiance += std::max(0.0, n[0] * w[0] + n[1] * w[1] + n[2] * w[2]) * radiance[c][k];
        }
        const double expected = irradiance * solid_angle / kPi;
        const double shown = preview.image.at(col, row)[c] * preview.shading_max;
        // The light has no band above 2, so its irradiance is exactly the renderer's order-2
        // shading (Funk-Hecke); what differs is the quadrature and the pixel's 3 x 3 subsamples
        // against its centre: bound 0.2 % of the ambient term's shading.
        const double ambient = light[c * 9] / (2.0 * std::sqrt(kPi));
        EXPECT_NEAR(shown, expected, 2e-3 * ambient) << col << ", " << row << ", " << c;
        worst = std::max(worst, std::abs(shown - expected) / ambient);
      }
      ++checked;
    }
  EXPECT_GT(checked, 50);

  // The panorama: the radiance itself at each pixel's direction (the guide lines' rows and
  // columns left out).
  int shown = 0;
  for (int row = 1; row < size; row += 5)
    for (int col = 1; col < 2 * size; col += 5) {
      if (row == size / 2 || col % (size / 2) == 0) continue;
      const std::array<double, 3> l =
          sh::light_eval(light, sh::equirect_direction((col + 0.5) / (2 * size), (row + 0.5) / size));
      if (std::min({l[0], l[1], l[2]}) < 0) continue;  // hatched
      ++shown;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(preview.image.at(size + col, row)[c] * preview.radiance_max, l[c], 1e-5 * preview.radiance_max);
    }
  EXPECT_GT(shown, 100);
  std::cout << "worst difference " << worst << " of the ambient shading\n";
}

}  // namespace
}  // namespace facetool
