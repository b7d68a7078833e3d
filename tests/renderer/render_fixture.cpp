// Loading of the sh_renderer plugin and random scenes for the renderer tests.
#include "render_fixture.h"

#include <cmath>
#include <memory>
#include <random>

#include "core/plugin/plugin_loader.h"
#include "core/sh/sh_projection.h"
#include "core/sh/sphere_samples.h"
#include "core/util/error.h"

namespace facetool::testing {

RendererPlugin& sh_renderer() {
  static PluginLoader loader;
  static std::shared_ptr<Plugin> object = [] {
    const PluginInfo& info = loader.load_file(FACETOOL_SH_RENDERER_PLUGIN);
    check(info.kind == FACETOOL_PLUGIN_RENDERER, "sh_renderer is not a renderer plugin");
    return loader.create(info);
  }();
  auto* renderer = dynamic_cast<RendererPlugin*>(object.get());
  check(renderer != nullptr, "sh_renderer's object is not a RendererPlugin");
  return *renderer;
}

HostScene random_scene(int64_t n, int64_t h, int64_t w, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  const int64_t pixels = h * w;
  HostScene s;
  s.n = n;
  s.h = h;
  s.w = w;
  s.albedo.resize(n * 3 * pixels);
  for (float& a : s.albedo) a = static_cast<float>(0.1 + 0.9 * u(rng));
  s.normal.resize(n * 3 * pixels);
  s.visibility.resize(n * 9 * pixels);
  const std::vector<sh::Vec3> dirs = sh::fibonacci_sphere(sh::kVisibilitySampleCount);
  for (int64_t b = 0; b < n; ++b)
    for (int64_t p = 0; p < pixels; ++p) {
      sh::Vec3 d{g(rng), g(rng), g(rng)};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double scale = (0.5 + 1.5 * u(rng)) / len;
      for (int a = 0; a < 3; ++a) s.normal[(b * 3 + a) * pixels + p] = static_cast<float>(d[a] * scale);
      // Up to three occluding caps (direction, cos of half-angle).
      std::vector<std::pair<sh::Vec3, double>> caps;
      const int count = static_cast<int>(u(rng) * 4.0);
      for (int c = 0; c < count; ++c) {
        sh::Vec3 axis{g(rng), g(rng), g(rng)};
        const double l = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        for (double& v : axis) v /= l;
        caps.push_back({axis, std::cos(0.2 + 0.8 * u(rng))});
      }
      const sh::ShCoeffs v = sh::project_function(dirs, [&](const sh::Vec3& w0) {
        for (const auto& [axis, cos_half] : caps)
          if (w0[0] * axis[0] + w0[1] * axis[1] + w0[2] * axis[2] > cos_half) return 0.0;
        return 1.0;
      });
      for (int j = 0; j < 9; ++j) s.visibility[(b * 9 + j) * pixels + p] = static_cast<float>(v[j]);
    }
  s.light.resize(n * 27);
  for (int64_t b = 0; b < n; ++b)
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 9; ++i)
        s.light[b * 27 + c * 9 + i] = static_cast<float>(i == 0 ? 1.0 + 2.0 * u(rng) : 2.0 * u(rng) - 1.0);
  return s;
}

RenderInputs upload(Backend& backend, const HostScene& s) {
  RenderInputs in;
  in.albedo = Tensor::from_host(backend, Shape{s.n, 3, s.h, s.w}, s.albedo);
  in.normal = Tensor::from_host(backend, Shape{s.n, 3, s.h, s.w}, s.normal);
  in.visibility = Tensor::from_host(backend, Shape{s.n, 9, s.h, s.w}, s.visibility);
  in.light = Tensor::from_host(backend, Shape{s.n, 27}, s.light);
  if (!s.mask.empty()) in.mask = Tensor::from_host(backend, Shape{s.n, 1, s.h, s.w}, s.mask);
  return in;
}

sh::ShCoeffs pixel_visibility(const HostScene& s, int64_t n, int64_t p) {
  sh::ShCoeffs v{};
  for (int j = 0; j < 9; ++j) v[j] = s.visibility[(n * 9 + j) * s.h * s.w + p];
  return v;
}

sh::Vec3 pixel_normal(const HostScene& s, int64_t n, int64_t p) {
  const int64_t pixels = s.h * s.w;
  return {s.normal[(n * 3 + 0) * pixels + p], s.normal[(n * 3 + 1) * pixels + p],
          s.normal[(n * 3 + 2) * pixels + p]};
}

sh::ShCoeffs image_light(const HostScene& s, int64_t n, int channel) {
  sh::ShCoeffs l{};
  for (int i = 0; i < 9; ++i) l[i] = s.light[n * 27 + channel * 9 + i];
  return l;
}

}  // namespace facetool::testing
