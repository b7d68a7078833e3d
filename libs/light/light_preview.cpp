// Rendering of the light preview: sphere shading and radiance panorama, tone-mapped per panel.
#include "libs/light/light_preview.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/sh/clamped_cosine.h"
#include "core/sh/sh_basis.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool::light {
namespace {

constexpr int kSubsamples = 3;  // per axis, on the sphere's outline pixels (smooth outline)
const std::array<float, 3> kBackground = {0.02f, 0.02f, 0.02f};
const std::array<float, 3> kHatch = {0.15f, 0.4f, 1.0f};
constexpr float kGuide = 0.3f;

using Rgb = std::array<double, 3>;

// One panel of linear values before tone mapping; `negative` marks pixels with a channel < 0.
struct Panel {
  int width = 0, height = 0;
  std::vector<Rgb> values;
  std::vector<char> negative;
  std::vector<char> inside;  // pixels the panel's content covers (the rest is background)
  std::vector<double> coverage;
};

// shading(n) = 1/pi * sum_i A_l L_i Y_i(n) per channel: the renderer's unoccluded shading. The
// factors A_l L_i / pi are computed once per light; a pixel then costs the 9 basis values.
using ShadingFactors = std::array<std::array<double, sh::kCoeffCount>, 3>;

ShadingFactors shading_factors(const sh::RgbLight& light) {
  ShadingFactors k{};
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < sh::kCoeffCount; ++i)
      k[c][i] = sh::cosine_band_factor(sh::sh_band(i)) * light[c * sh::kCoeffCount + i] / kPi;
  return k;
}

Rgb sphere_shading(const ShadingFactors& k, const sh::Vec3& n) {
  double y[sh::kCoeffCount];
  sh::sh_basis(n[0], n[1], n[2], y);
  Rgb out{};
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < sh::kCoeffCount; ++i) out[c] += k[c][i] * y[i];
  return out;
}

Panel render_sphere(const sh::RgbLight& light, int size) {
  Panel panel{size, size, {}, {}, {}, {}};
  const size_t count = static_cast<size_t>(size) * size;
  panel.values.assign(count, Rgb{});
  panel.negative.assign(count, 0);
  panel.inside.assign(count, 0);
  panel.coverage.assign(count, 0.0);
  const double radius = 0.5 * size * 0.94;  // a small margin around the sphere
  const double centre = 0.5 * size;
  const ShadingFactors k = shading_factors(light);
  for (int row = 0; row < size; ++row)
    for (int col = 0; col < size; ++col) {
      const size_t p = static_cast<size_t>(row) * size + col;
      Rgb sum{};
      int hits = 0;
      // A pixel wholly inside the sphere is shaded once, at its centre (the shading varies too
      // little across one pixel to show); a pixel on the outline is subsampled for its coverage.
      const double far_x = std::max(std::abs(col - centre), std::abs(col + 1 - centre));
      const double far_y = std::max(std::abs(row - centre), std::abs(row + 1 - centre));
      const int n = far_x * far_x + far_y * far_y < radius * radius ? 1 : kSubsamples;
      for (int sy = 0; sy < n; ++sy)
        for (int sx = 0; sx < n; ++sx) {
          const double x = (col + (sx + 0.5) / n - centre) / radius;
          const double y = -(row + (sy + 0.5) / n - centre) / radius;  // rows go down
          const double r2 = x * x + y * y;
          if (r2 > 1.0) continue;
          const Rgb s = sphere_shading(k, {x, y, std::sqrt(1.0 - r2)});
          for (int c = 0; c < 3; ++c) sum[c] += s[c];
          ++hits;
        }
      if (hits == 0) continue;
      panel.inside[p] = 1;
      panel.coverage[p] = static_cast<double>(hits) / (n * n);
      for (int c = 0; c < 3; ++c) panel.values[p][c] = sum[c] / hits;
      panel.negative[p] = *std::min_element(panel.values[p].begin(), panel.values[p].end()) < 0;
    }
  return panel;
}

Panel render_panorama(const sh::RgbLight& light, int height) {
  const int width = 2 * height;
  Panel panel{width, height, {}, {}, {}, {}};
  const size_t count = static_cast<size_t>(width) * height;
  panel.values.assign(count, Rgb{});
  panel.negative.assign(count, 0);
  panel.inside.assign(count, 1);
  panel.coverage.assign(count, 1.0);
  // sh::equirect_direction's mapping, its sines and cosines once per row and per column.
  std::vector<double> sin_phi(width), cos_phi(width);
  for (int col = 0; col < width; ++col) {
    const double phi = 2.0 * kPi * ((col + 0.5) / width - 0.5);
    sin_phi[col] = std::sin(phi);
    cos_phi[col] = std::cos(phi);
  }
  for (int row = 0; row < height; ++row) {
    const double theta = kPi * ((row + 0.5) / height);
    const double sin_theta = std::sin(theta), cos_theta = std::cos(theta);
    for (int col = 0; col < width; ++col) {
      const size_t p = static_cast<size_t>(row) * width + col;
      const sh::Vec3 d{sin_theta * sin_phi[col], cos_theta, -sin_theta * cos_phi[col]};
      double y[sh::kCoeffCount];
      sh::sh_basis(d[0], d[1], d[2], y);  // once for the three channels
      for (int c = 0; c < 3; ++c)
        for (int i = 0; i < sh::kCoeffCount; ++i) panel.values[p][c] += light[c * sh::kCoeffCount + i] * y[i];
      panel.negative[p] = *std::min_element(panel.values[p].begin(), panel.values[p].end()) < 0;
    }
  }
  return panel;
}

double largest_value(const Panel& panel) {
  double largest = 0.0;
  for (size_t p = 0; p < panel.values.size(); ++p)
    if (panel.inside[p])
      for (double v : panel.values[p]) largest = std::max(largest, v);
  return largest;
}

bool on_hatch(int x, int y) { return (x + y) % 8 < 2; }

// Copies `panel`, divided by its largest value, into `out` at column `left`.
void paint(const Panel& panel, RgbImage& out, int left) {
  const double largest = largest_value(panel);
  const double scale = largest > 0.0 ? 1.0 / largest : 1.0;
  for (int row = 0; row < panel.height; ++row)
    for (int col = 0; col < panel.width; ++col) {
      const size_t p = static_cast<size_t>(row) * panel.width + col;
      float* target = out.at(left + col, row);
      const double a = panel.coverage[p];
      for (int c = 0; c < 3; ++c) {
        double v = std::max(0.0, panel.values[p][c]) * scale;
        if (panel.negative[p] && on_hatch(left + col, row)) v = kHatch[c];
        target[c] = static_cast<float>(a * v + (1.0 - a) * kBackground[c]);
      }
    }
}

// Dotted guide lines on the panorama: the horizon and the columns of -X, -Z and +X.
void draw_guides(RgbImage& out, int left, int height) {
  const int width = 2 * height;
  auto mark = [&](int x, int y) {
    if ((x / 2 + y / 2) % 2) return;  // dotted
    float* target = out.at(left + x, y);
    for (int c = 0; c < 3; ++c) target[c] = 0.5f * target[c] + 0.5f * kGuide;
  };
  for (int x = 0; x < width; ++x) mark(x, height / 2);
  for (int quarter = 1; quarter <= 3; ++quarter)
    for (int y = 0; y < height; ++y) mark(quarter * width / 4, y);
}

}  // namespace

LightPreview render_light_preview(const sh::RgbLight& light, int size) {
  check(size >= 16 && size <= 4096, "light preview size ", size, " is out of range: use 16..4096");
  for (double v : light)
    check(std::isfinite(v), "cannot show a light holding a non-finite coefficient");
  const Panel sphere = render_sphere(light, size);
  const Panel panorama = render_panorama(light, size);

  LightPreview preview;
  preview.image.width = 3 * size;
  preview.image.height = size;
  preview.image.pixels.assign(static_cast<size_t>(3 * size) * size * 3, 0.0f);
  paint(sphere, preview.image, 0);
  paint(panorama, preview.image, size);
  draw_guides(preview.image, size, size);

  preview.shading_max = largest_value(sphere);
  preview.radiance_max = largest_value(panorama);
  preview.radiance_min = panorama.values.front()[0];
  for (const Rgb& v : panorama.values)
    for (double c : v) preview.radiance_min = std::min(preview.radiance_min, c);
  for (size_t p = 0; p < sphere.negative.size(); ++p)
    if (sphere.inside[p] && sphere.negative[p]) preview.negative_shading = true;
  return preview;
}

LightPreview write_light_preview(const std::string& path, const sh::RgbLight& light, int size) {
  LightPreview preview = render_light_preview(light, size);
  write_png_atomically(path, preview.image);
  return preview;
}

}  // namespace facetool::light
