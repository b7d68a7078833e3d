// Backward tests of the sh_renderer on cpu: finite differences, blocked and accumulated gradients.
#include <gtest/gtest.h>

#include <random>

#include "core/backend/registry.h"
#include "core/plugin/renderer_autograd.h"
#include "render_fixture.h"
#include "tests/support/finite_difference.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

// loss = sum(w_image * image) + sum(w_shading * shading), accumulated in double on the host.
struct Loss {
  std::vector<float> w_image, w_shading;
  double operator()(const HostScene& s) const {
    RenderOutputs out;
    sh_renderer().forward(upload(get_backend("cpu"), s), out);
    const std::vector<float> image = out.image.to_host(), shading = out.shading.to_host();
    double total = 0.0;
    for (size_t k = 0; k < image.size(); ++k)
      total += double(w_image[k]) * image[k] + double(w_shading[k]) * shading[k];
    return total;
  }
};

Loss random_loss(const HostScene& s, unsigned seed) {
  const size_t count = static_cast<size_t>(s.n * 3 * s.h * s.w);
  return {random_values(count, seed), random_values(count, seed + 1)};
}

struct Grads {
  Tensor albedo, normal, visibility, light;
};

Grads analytic(const HostScene& s, const Loss& loss) {
  Backend& cpu = get_backend("cpu");
  const RenderInputs in = upload(cpu, s);
  const Shape rgb{s.n, 3, s.h, s.w};
  const Tensor d_image = Tensor::from_host(cpu, rgb, loss.w_image);
  const Tensor d_shading = Tensor::from_host(cpu, rgb, loss.w_shading);
  Grads g{Tensor::empty(cpu, rgb), Tensor::empty(cpu, rgb),
          Tensor::empty(cpu, Shape{s.n, 9, s.h, s.w}), Tensor::empty(cpu, Shape{s.n, 27})};
  RenderGradients targets;
  targets.albedo.tensor = &g.albedo;
  targets.normal.tensor = &g.normal;
  targets.visibility.tensor = &g.visibility;
  targets.light.tensor = &g.light;
  sh_renderer().backward(in, &d_image, &d_shading, targets);
  return g;
}

std::vector<float> finite_difference(const HostScene& s, const Loss& loss,
                                     std::vector<float> HostScene::*field, double eps) {
  std::vector<float> grad((s.*field).size());
  HostScene moved = s;
  for (size_t k = 0; k < grad.size(); ++k)
    grad[k] = static_cast<float>(central_difference((moved.*field)[k], eps, [&] { return loss(moved); }));
  return grad;
}

TEST(ShRendererBackward, MatchesFiniteDifferences) {
  HostScene s = random_scene(2, 2, 3, 5);
  s.mask.assign(static_cast<size_t>(s.n * s.h * s.w), 1.0f);
  s.mask[4] = 0.0f;  // one pixel outside: its gradients must be zero (and FD agrees)
  const Loss loss = random_loss(s, 50);
  const Grads g = analytic(s, loss);
  // albedo, visibility and light enter linearly: large steps have no truncation error.
  EXPECT_TRUE(all_close(g.albedo.to_host(), finite_difference(s, loss, &HostScene::albedo, 0.05), 1e-4, 1e-3));
  EXPECT_TRUE(all_close(g.visibility.to_host(), finite_difference(s, loss, &HostScene::visibility, 0.05), 1e-4, 1e-3));
  EXPECT_TRUE(all_close(g.light.to_host(), finite_difference(s, loss, &HostScene::light, 0.05), 1e-4, 1e-3));
  EXPECT_TRUE(all_close(g.normal.to_host(), finite_difference(s, loss, &HostScene::normal, 3e-3), 2e-3, 1e-2));
  const std::vector<float> dn = g.normal.to_host();
  for (int a = 0; a < 3; ++a) EXPECT_EQ(dn[a * 6 + 4], 0.0f);  // image 0, pixel 4, masked
}

TEST(ShRendererBackward, LightGradientOverManyPixelsUsesMultiStageReduction) {
  const HostScene s = random_scene(1, 40, 45, 6);  // 1800 pixels: 8 chunks, two passes
  const Loss loss = random_loss(s, 60);
  const Grads g = analytic(s, loss);
  EXPECT_TRUE(all_close(g.light.to_host(), finite_difference(s, loss, &HostScene::light, 0.1), 1e-3, 1e-3));
}

TEST(ShRendererBackward, BlockedGradientsAreUntouchedAndOthersUnchanged) {
  Backend& cpu = get_backend("cpu");
  const HostScene s = random_scene(1, 3, 2, 7);
  const Loss loss = random_loss(s, 70);
  const Grads full = analytic(s, loss);
  const RenderInputs in = upload(cpu, s);
  const Tensor d_image = Tensor::from_host(cpu, Shape{1, 3, 3, 2}, loss.w_image);
  const Tensor d_shading = Tensor::from_host(cpu, Shape{1, 3, 3, 2}, loss.w_shading);
  // Only the normal and the light: the sentinel-filled albedo/visibility tensors stay as they are
  // (they are not passed), so a blocked gradient is exactly zero work.
  const Tensor dn = Tensor::full(cpu, Shape{1, 3, 3, 2}, 0.5f);
  const Tensor dl = Tensor::full(cpu, Shape{1, 27}, 0.25f);
  RenderGradients t;
  t.normal = {&dn, true};  // accumulate onto 0.5
  t.light = {&dl, true};   // accumulate onto 0.25
  sh_renderer().backward(in, &d_image, &d_shading, t);
  std::vector<float> expected_n = full.normal.to_host(), expected_l = full.light.to_host();
  for (float& v : expected_n) v += 0.5f;
  for (float& v : expected_l) v += 0.25f;
  EXPECT_TRUE(all_close(dn.to_host(), expected_n, 1e-6, 1e-6));
  EXPECT_TRUE(all_close(dl.to_host(), expected_l, 1e-6, 1e-6));

  // Only the visibility, with no incoming shading gradient: equals d_image's share alone.
  const Tensor dv = Tensor::full(cpu, Shape{1, 9, 3, 2}, 7.0f);
  RenderGradients only_v;
  only_v.visibility = {&dv, false};
  sh_renderer().backward(in, &d_image, nullptr, only_v);
  Loss image_only = loss;
  std::fill(image_only.w_shading.begin(), image_only.w_shading.end(), 0.0f);
  EXPECT_TRUE(all_close(dv.to_host(), analytic(s, image_only).visibility.to_host(), 1e-6, 1e-6));

  // No incoming gradient at all: overwritten targets become exactly zero.
  const Tensor da = Tensor::full(cpu, Shape{1, 3, 3, 2}, 3.0f);
  RenderGradients only_a;
  only_a.albedo = {&da, false};
  sh_renderer().backward(in, nullptr, nullptr, only_a);
  for (float v : da.to_host()) EXPECT_EQ(v, 0.0f);
}

TEST(ShRendererBackward, ZeroLengthNormalHasZeroGradient) {
  HostScene s = random_scene(1, 1, 2, 8);
  for (int a = 0; a < 3; ++a) s.normal[a * 2 + 1] = 0.0f;
  const Loss loss = random_loss(s, 80);
  const Grads g = analytic(s, loss);
  const std::vector<float> dn = g.normal.to_host(), dv = g.visibility.to_host(),
                           da = g.albedo.to_host();
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(dn[a * 2 + 1], 0.0f);
    EXPECT_EQ(da[a * 2 + 1], 0.0f);
  }
  for (int j = 0; j < 9; ++j) EXPECT_EQ(dv[j * 2 + 1], 0.0f);
}

}  // namespace
}  // namespace facetool::testing


namespace facetool::testing {
namespace {

TEST(ShRendererAutograd, MatchesThePluginBackwardAndBlocksVisibility) {
  Backend& cpu = get_backend("cpu");
  const HostScene s = random_scene(1, 2, 3, 10);
  Loss loss = random_loss(s, 100);
  std::fill(loss.w_shading.begin(), loss.w_shading.end(), 0.0f);
  const Grads expected = analytic(s, loss);
  const RenderInputs in = upload(cpu, s);
  ag::Variable albedo(in.albedo, true), normal(in.normal, true), light(in.light, true);
  ag::Variable visibility(in.visibility, true);
  ag::Variable image =
      render_image(sh_renderer(), albedo, normal, ag::stop_gradient(visibility), light);
  image.backward(Tensor::from_host(cpu, Shape{1, 3, 2, 3}, loss.w_image));
  EXPECT_TRUE(all_close(albedo.grad().to_host(), expected.albedo.to_host(), 1e-6, 1e-6));
  EXPECT_TRUE(all_close(normal.grad().to_host(), expected.normal.to_host(), 1e-6, 1e-6));
  EXPECT_TRUE(all_close(light.grad().to_host(), expected.light.to_host(), 1e-6, 1e-6));
  EXPECT_FALSE(visibility.has_grad());
}

}  // namespace
}  // namespace facetool::testing
