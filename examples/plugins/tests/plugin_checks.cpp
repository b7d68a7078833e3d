// Checks of the example plugins through the installed SDK only: the L1 term against a plain
// computation, the Lambertian renderer against its closed form, against sh_renderer with an
// all-open visibility and against finite differences (cpu, and opencl where present), and the
// compact network's outputs and light branch.
// usage: plugin_checks L1 LAMBERTIAN NETWORK SH_RENDERER
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/autograd/functions.h"
#include "core/backend/registry.h"
#include "core/plugin/loss_plugin.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/plugin_loader.h"
#include "core/plugin/renderer_plugin.h"
#include "core/util/error.h"

namespace {

namespace ag = facetool::ag;
using facetool::Backend;
using facetool::Shape;
using facetool::Tensor;

int failures = 0;
std::mt19937 rng(7);

void expect_near(double got, double want, double tolerance, const std::string& what) {
  if (!(std::abs(got - want) <= tolerance * (1.0 + std::abs(want)))) {
    std::printf("FAIL %s: got %.7g, want %.7g\n", what.c_str(), got, want);
    ++failures;
  }
}

std::vector<float> random_values(size_t n, float lo, float hi) {
  std::uniform_real_distribution<float> d(lo, hi);
  std::vector<float> v(n);
  for (float& x : v) x = d(rng);
  return v;
}

template <class Kind>
std::shared_ptr<Kind> load(facetool::PluginLoader& loader, const std::string& file) {
  std::shared_ptr<facetool::Plugin> object = loader.create(loader.load_file(file));
  auto typed = std::dynamic_pointer_cast<Kind>(object);
  facetool::check(typed != nullptr, file, " is not a plugin of the expected kind");
  return typed;
}

// c_i = A_l Y_i(n) in double, written out independently of the kernels.
std::vector<double> cosine_coefficients(double x, double y, double z) {
  const double pi = 3.14159265358979323846;
  const double a0 = pi, a1 = 2.0 * pi / 3.0, a2 = pi / 4.0;
  return {a0 * 0.5 * std::sqrt(1.0 / pi),
          a1 * std::sqrt(3.0 / (4.0 * pi)) * y,
          a1 * std::sqrt(3.0 / (4.0 * pi)) * z,
          a1 * std::sqrt(3.0 / (4.0 * pi)) * x,
          a2 * 0.5 * std::sqrt(15.0 / pi) * x * y,
          a2 * 0.5 * std::sqrt(15.0 / pi) * y * z,
          a2 * 0.25 * std::sqrt(5.0 / pi) * (3.0 * z * z - 1.0),
          a2 * 0.5 * std::sqrt(15.0 / pi) * x * z,
          a2 * 0.25 * std::sqrt(15.0 / pi) * (x * x - y * y)};
}

void check_l1(facetool::LossPlugin& l1, facetool::RendererPlugin& renderer, Backend& be) {
  const Shape rgb{2, 3, 4, 4}, grey{2, 1, 4, 4};
  const std::vector<float> a = random_values(96, 0, 1), b = random_values(96, 0, 1);
  std::vector<float> m = random_values(32, 0, 1);
  for (float& v : m) v = v > 0.4f ? 1.0f : 0.0f;
  m[0] = 1.0f;
  facetool::NetworkOutputs predicted;
  predicted.albedo = ag::Variable(Tensor::from_host(be, rgb, a), true);
  facetool::LossTargets targets;
  targets.albedo = Tensor::from_host(be, rgb, b);
  targets.mask = Tensor::from_host(be, grey, m);
  const ag::Variable loss = l1.evaluate("l1_albedo", predicted, targets, renderer);
  loss.backward();
  double sum = 0, count = 0;
  for (int n = 0; n < 2; ++n)
    for (int p = 0; p < 16; ++p) {
      count += m[n * 16 + p];
      for (int c = 0; c < 3; ++c) {
        const int at = (n * 3 + c) * 16 + p;
        sum += std::abs(a[at] - b[at]) * m[n * 16 + p];
      }
    }
  expect_near(loss.value().to_host()[0], sum / (3 * count), 1e-5, "l1_albedo value");
  const std::vector<float> grad = predicted.albedo.grad().to_host();
  for (int at : {0, 17, 50, 95}) {
    const int pixel = (at / 48) * 16 + at % 16;
    const double sign = a[at] > b[at] ? 1.0 : -1.0;
    expect_near(grad[at], sign * m[pixel] / (3 * count), 1e-5, "l1_albedo gradient");
  }
}

struct Scene {
  std::vector<float> albedo, normal, light, mask;
};

std::vector<float> render(facetool::RendererPlugin& r, Backend& be, const Scene& s, int n, int h,
                          int w, const std::vector<float>* visibility = nullptr) {
  facetool::RenderInputs in;
  in.albedo = Tensor::from_host(be, Shape{n, 3, h, w}, s.albedo);
  in.normal = Tensor::from_host(be, Shape{n, 3, h, w}, s.normal);
  in.light = Tensor::from_host(be, Shape{n, 27}, s.light);
  if (!s.mask.empty()) in.mask = Tensor::from_host(be, Shape{n, 1, h, w}, s.mask);
  if (visibility) in.visibility = Tensor::from_host(be, Shape{n, 9, h, w}, *visibility);
  facetool::RenderOutputs out;
  r.forward(in, out);
  return out.image.to_host();
}

void check_lambertian(facetool::RendererPlugin& lambertian, facetool::RendererPlugin& sh,
                      Backend& be, Backend* opencl) {
  const int n = 2, h = 3, w = 5, px = h * w;
  Scene s{random_values(n * 3 * px, 0.1f, 1), random_values(n * 3 * px, -1, 1),
          random_values(n * 27, -0.5f, 1), {}};
  // Closed form: one normal (not unit) everywhere in image 0.
  for (int p = 0; p < px; ++p) {
    s.normal[0 * px + p] = 0.3f;
    s.normal[1 * px + p] = -0.5f;
    s.normal[2 * px + p] = 0.8f;
  }
  const std::vector<float> image = render(lambertian, be, s, n, h, w);
  const double len = std::sqrt(0.09 + 0.25 + 0.64);
  const std::vector<double> c = cosine_coefficients(0.3 / len, -0.5 / len, 0.8 / len);
  for (int ch = 0; ch < 3; ++ch) {
    double shading = 0;
    for (int i = 0; i < 9; ++i) shading += s.light[ch * 9 + i] * c[i];
    shading /= 3.14159265358979323846;
    for (int p : {0, 7, 14})
      expect_near(image[ch * px + p], s.albedo[ch * px + p] * shading, 1e-5,
                  "closed-form shading, channel " + std::to_string(ch));
  }
  // sh_renderer with visibility 1 over the whole sphere (v_0 = 2 sqrt(pi)) is the same model.
  std::vector<float> open(n * 9 * px, 0.0f);
  for (int k = 0; k < n; ++k)
    for (int p = 0; p < px; ++p) open[k * 9 * px + p] = 2.0f * std::sqrt(3.14159265358979f);
  const std::vector<float> reference = render(sh, be, s, n, h, w, &open);
  for (size_t i = 0; i < image.size(); ++i)
    expect_near(image[i], reference[i], 1e-4, "against sh_renderer at " + std::to_string(i));
  // Masked-out pixels are 0.
  Scene masked = s;
  masked.mask.assign(n * px, 1.0f);
  masked.mask[3] = 0.0f;
  const std::vector<float> with_mask = render(lambertian, be, masked, n, h, w);
  expect_near(with_mask[3], 0.0, 0.0, "masked pixel");
  expect_near(with_mask[4], image[4], 1e-6, "unmasked pixel");

  // Every gradient entry of sum(weights * image) against central differences.
  const std::vector<float> weights = random_values(n * 3 * px, -1, 1);
  auto objective = [&](const Scene& scene) {
    const std::vector<float> img = render(lambertian, be, scene, n, h, w);
    double total = 0;
    for (size_t i = 0; i < img.size(); ++i) total += double(weights[i]) * img[i];
    return total;
  };
  facetool::RenderInputs in;
  in.albedo = Tensor::from_host(be, Shape{n, 3, h, w}, s.albedo);
  in.normal = Tensor::from_host(be, Shape{n, 3, h, w}, s.normal);
  in.light = Tensor::from_host(be, Shape{n, 27}, s.light);
  const Tensor d_image = Tensor::from_host(be, Shape{n, 3, h, w}, weights);
  const Tensor ga = Tensor::zeros(be, Shape{n, 3, h, w}), gn = Tensor::zeros(be, Shape{n, 3, h, w});
  const Tensor gl = Tensor::zeros(be, Shape{n, 27});
  facetool::RenderGradients g;
  g.albedo = {&ga, false};
  g.normal = {&gn, false};
  g.light = {&gl, false};
  lambertian.backward(in, &d_image, nullptr, g);
  const std::vector<float> grads[3] = {ga.to_host(), gn.to_host(), gl.to_host()};
  const char* names[3] = {"albedo", "normal", "light"};
  for (int which = 0; which < 3; ++which)
    for (int index = 0; index < static_cast<int>(grads[which].size()); ++index) {
      Scene plus = s, minus = s;
      std::vector<float>* fields[2][3] = {{&plus.albedo, &plus.normal, &plus.light},
                                          {&minus.albedo, &minus.normal, &minus.light}};
      const float eps = 1e-2f;
      (*fields[0][which])[index] += eps;
      (*fields[1][which])[index] -= eps;
      const double numeric = (objective(plus) - objective(minus)) / (2 * eps);
      expect_near(grads[which][index], numeric, 3e-3,
                  std::string("d/d ") + names[which] + "[" + std::to_string(index) + "]");
    }

  if (!opencl) return;
  const std::vector<float> on_device = render(lambertian, *opencl, s, n, h, w);
  for (size_t i = 0; i < image.size(); ++i)
    expect_near(on_device[i], image[i], 1e-4, "opencl forward against its CPU twin");
  facetool::RenderInputs din;
  din.albedo = Tensor::from_host(*opencl, Shape{n, 3, h, w}, s.albedo);
  din.normal = Tensor::from_host(*opencl, Shape{n, 3, h, w}, s.normal);
  din.light = Tensor::from_host(*opencl, Shape{n, 27}, s.light);
  const Tensor dd = Tensor::from_host(*opencl, Shape{n, 3, h, w}, weights);
  const Tensor dga = Tensor::zeros(*opencl, Shape{n, 3, h, w});
  const Tensor dgn = Tensor::zeros(*opencl, Shape{n, 3, h, w});
  const Tensor dgl = Tensor::zeros(*opencl, Shape{n, 27});
  facetool::RenderGradients dg;
  dg.albedo = {&dga, false};
  dg.normal = {&dgn, false};
  dg.light = {&dgl, false};
  lambertian.backward(din, &dd, nullptr, dg);
  const std::vector<float> device_grads[3] = {dga.to_host(), dgn.to_host(), dgl.to_host()};
  for (int which = 0; which < 3; ++which)
    for (size_t i = 0; i < grads[which].size(); ++i)
      expect_near(device_grads[which][i], grads[which][i], 1e-4,
                  std::string("opencl ") + names[which] + " gradient against its CPU twin");
  std::printf("lambertian: the OpenCL kernels match their CPU twins\n");
}

void check_network(facetool::NetworkPlugin& net, Backend& be) {
  net.build(be, facetool::NetworkConfig{4, 16});
  net.init_random(3);
  bool light_branch = false;
  for (const auto& [name, p] : net.parameters())
    if (name == "light_fc.weight") light_branch = p.shape() == Shape{27, 8};
  if (!light_branch) {
    std::printf("FAIL compact_network: light_fc.weight is not [27, 8] (2 x width)\n");
    ++failures;
  }
  const ag::Variable images(Tensor::from_host(be, Shape{2, 3, 16, 16}, random_values(1536, 0, 1)));
  const facetool::NetworkOutputs out = net.forward(images, false);
  const std::vector<float> normal = out.normal.value().to_host();
  for (int p : {0, 100, 255}) {
    const double x = normal[p], y = normal[256 + p], z = normal[512 + p];
    expect_near(std::sqrt(x * x + y * y + z * z), 1.0, 1e-4, "unit normal");
  }
  if (!(out.visibility.shape() == Shape{2, 9, 16, 16}) || !(out.light.shape() == Shape{2, 27}) ||
      !(out.albedo.shape() == Shape{2, 3, 16, 16})) {
    std::printf("FAIL compact_network: output shapes\n");
    ++failures;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: plugin_checks L1 LAMBERTIAN NETWORK SH_RENDERER\n");
    return 2;
  }
  try {
    facetool::PluginLoader loader;
    auto l1 = load<facetool::LossPlugin>(loader, argv[1]);
    auto lambertian = load<facetool::RendererPlugin>(loader, argv[2]);
    auto network = load<facetool::NetworkPlugin>(loader, argv[3]);
    auto sh = load<facetool::RendererPlugin>(loader, argv[4]);
    Backend& cpu = facetool::get_backend("cpu");
    Backend* opencl = nullptr;
    try {
      opencl = &facetool::get_backend("opencl");
    } catch (const facetool::Error& e) {
      std::printf("no opencl backend here (%s): cpu only\n", e.what());
    }
    check_l1(*l1, *lambertian, cpu);
    check_lambertian(*lambertian, *sh, cpu, opencl);
    check_network(*network, cpu);
  } catch (const std::exception& e) {
    std::printf("FAIL: %s\n", e.what());
    return 1;
  }
  std::printf(failures ? "%d check(s) failed\n" : "example plugins: all checks passed\n", failures);
  return failures ? 1 : 0;
}
