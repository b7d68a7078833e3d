// Renderer benchmarks: timed forward and backward passes with medians over repeats.
#include "apps/facetool/bench/render_benchmarks.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "core/backend/backend.h"

namespace facetool {
namespace {

Tensor random_tensor(Backend& be, const Shape& shape, unsigned seed, float lo, float hi) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  std::vector<float> v(static_cast<size_t>(shape.numel()));
  for (float& x : v) x = dist(rng);
  return Tensor::from_host(be, shape, v);
}

template <typename F>
double median_ms(Backend& be, int repeats, F&& work) {
  std::vector<double> runs;
  for (int r = 0; r <= repeats; ++r) {
    be.synchronize();
    const auto start = std::chrono::steady_clock::now();
    work();
    be.synchronize();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (r > 0) runs.push_back(ms);  // run 0 compiles kernels and fills caches
  }
  std::sort(runs.begin(), runs.end());
  return runs[runs.size() / 2];
}

}  // namespace

void run_render_benchmarks(RendererPlugin& renderer, Backend& be, int batch, int size,
                           int repeats, std::ostream& out) {
  RenderInputs in;
  in.albedo = random_tensor(be, Shape{batch, 3, size, size}, 1, 0.0f, 1.0f);
  in.normal = random_tensor(be, Shape{batch, 3, size, size}, 2, -1.0f, 1.0f);
  in.visibility = random_tensor(be, Shape{batch, 9, size, size}, 3, -1.0f, 1.0f);
  in.light = random_tensor(be, Shape{batch, 27}, 4, -1.0f, 1.0f);
  RenderOutputs result;
  const Tensor d_image = random_tensor(be, Shape{batch, 3, size, size}, 5, -1.0f, 1.0f);
  const Tensor da = Tensor::empty(be, in.albedo.shape()), dn = Tensor::empty(be, in.normal.shape());
  const Tensor dv = Tensor::empty(be, in.visibility.shape()), dl = Tensor::empty(be, in.light.shape());
  RenderGradients g;
  g.albedo = {&da, false};
  g.normal = {&dn, false};
  g.visibility = {&dv, false};
  g.light = {&dl, false};

  const double fwd = median_ms(be, repeats, [&] { renderer.forward(in, result); });
  const double bwd = median_ms(be, repeats, [&] { renderer.backward(in, &d_image, nullptr, g); });
  char line[200];
  out << "renderer " << renderer.name() << " on " << be.name() << " (" << be.device_description()
      << "), batch " << batch << " x " << size << "x" << size << "\n";
  std::snprintf(line, sizeof line, "%-34s %10s %14s\n", "benchmark", "ms", "Mpixels/s");
  out << line;
  const double mpix = static_cast<double>(batch) * size * size / 1e6;
  std::snprintf(line, sizeof line, "%-34s %10.1f %14.1f\n", "forward (image + shading)", fwd, mpix / (fwd / 1000));
  out << line;
  std::snprintf(line, sizeof line, "%-34s %10.1f %14.1f\n", "backward (all four gradients)", bwd, mpix / (bwd / 1000));
  out << line;
  std::snprintf(line, sizeof line, "%-34s %10.1f %14.1f\n", "forward + backward", fwd + bwd, mpix / ((fwd + bwd) / 1000));
  out << line << std::flush;
}

}  // namespace facetool
