// Autograd wrapper of a RendererPlugin: the rendered image as an ag::Variable with a backward.
#pragma once

#include <vector>

#include "core/autograd/variable.h"
#include "core/plugin/renderer_plugin.h"

namespace facetool {

// image = renderer(albedo, normal, visibility, light) restricted to `mask` (undefined = all).
// Gradients reach whichever inputs require them; wrap one in ag::stop_gradient to block it.
// The renderer must outlive the graph. Shading is not returned (use the plugin directly).
inline ag::Variable render_image(RendererPlugin& renderer, const ag::Variable& albedo,
                                 const ag::Variable& normal, const ag::Variable& visibility,
                                 const ag::Variable& light, const Tensor& mask = Tensor()) {
  RenderInputs in{albedo.value(), normal.value(), visibility.value(), light.value(), mask};
  RenderOutputs out;
  renderer.forward(in, out);
  return ag::make_result(
      out.image, "render_image", {albedo, normal, visibility, light},
      [&renderer, in](const Tensor& grad, const std::vector<ag::GradTarget>& targets) {
        RenderGradients g;
        GradientTarget* slots[4] = {&g.albedo, &g.normal, &g.visibility, &g.light};
        for (size_t k = 0; k < 4 && k < targets.size(); ++k)
          *slots[k] = {targets[k].tensor, targets[k].accumulate};
        renderer.backward(in, &grad, nullptr, g);
      });
}

}  // namespace facetool
