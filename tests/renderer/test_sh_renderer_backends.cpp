// The sh_renderer on every non-reference backend (opencl) against the cpu, forward and backward.
#include <gtest/gtest.h>

#include "core/backend/registry.h"
#include "render_fixture.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

std::vector<std::vector<float>> run(Backend& backend, const HostScene& s) {
  const RenderInputs in = upload(backend, s);
  RenderOutputs out;
  sh_renderer().forward(in, out);
  const Shape rgb{s.n, 3, s.h, s.w};
  const size_t count = static_cast<size_t>(rgb.numel());
  const Tensor d_image = Tensor::from_host(backend, rgb, random_values(count, 90));
  const Tensor d_shading = Tensor::from_host(backend, rgb, random_values(count, 91));
  const Tensor da = Tensor::empty(backend, rgb), dn = Tensor::empty(backend, rgb),
               dv = Tensor::empty(backend, Shape{s.n, 9, s.h, s.w}),
               dl = Tensor::full(backend, Shape{s.n, 27}, 1.0f);
  RenderGradients g;
  g.albedo = {&da, false};
  g.normal = {&dn, false};
  g.visibility = {&dv, false};
  g.light = {&dl, true};
  sh_renderer().backward(in, &d_image, &d_shading, g);
  return {out.image.to_host(), out.shading.to_host(), da.to_host(), dn.to_host(), dv.to_host(),
          dl.to_host()};
}

TEST(ShRendererBackends, AgreeWithCpu) {
  const std::vector<std::string> backends = non_reference_backends();
  if (backends.empty()) GTEST_SKIP() << "no non-reference backend (opencl) can run here";
  HostScene s = random_scene(2, 17, 19, 9);  // 323 pixels: partial chunks and two passes
  s.mask.assign(static_cast<size_t>(s.n * s.h * s.w), 1.0f);
  for (size_t p = 0; p < s.mask.size(); p += 7) s.mask[p] = 0.0f;
  const auto reference = run(get_backend("cpu"), s);
  const char* names[] = {"image", "shading", "d_albedo", "d_normal", "d_visibility", "d_light"};
  for (const std::string& name : backends) {
    const auto other = run(get_backend(name), s);
    for (size_t k = 0; k < reference.size(); ++k)
      EXPECT_TRUE(all_close(other[k], reference[k], 1e-5, 1e-4)) << name << " " << names[k];
  }
}

}  // namespace
}  // namespace facetool::testing
