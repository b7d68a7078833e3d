// The renderer plugin interface: differentiable image formation from albedo, normal, visibility, light.
#pragma once

#include <string>

#include "core/plugin/plugin.h"
#include "core/tensor/tensor.h"

namespace facetool {

// Inputs of one render; all tensors live on the same backend. N images of H x W pixels.
struct RenderInputs {
  Tensor albedo;      // [N,3,H,W]
  Tensor normal;      // [N,3,H,W] world-frame normals of any length, normalised per pixel
  Tensor visibility;  // [N,9,H,W] SH coefficients of the visibility v(w) per pixel
  Tensor light;       // [N,27] SH light per image, channel-major R0..R8 G0..G8 B0..B8
  Tensor mask;        // [N,1,H,W] or undefined (= every pixel); rendered where mask > 0.5
};

// Outputs; tensors left undefined are allocated by forward() on the inputs' backend.
struct RenderOutputs {
  Tensor image;    // [N,3,H,W] = albedo * shading
  Tensor shading;  // [N,3,H,W]
};

// Where one gradient goes: nullptr = blocked (not computed, never written); otherwise
// overwritten, or added to when `accumulate` is set.
struct GradientTarget {
  const Tensor* tensor = nullptr;
  bool accumulate = false;
};

struct RenderGradients {
  GradientTarget albedo;      // [N,3,H,W]
  GradientTarget normal;      // [N,3,H,W] (through the normalisation)
  GradientTarget visibility;  // [N,9,H,W]
  GradientTarget light;       // [N,27]
};

// A renderer plugin (kind FACETOOL_PLUGIN_RENDERER). Implementations throw facetool::Error for
// inputs of the wrong shape or backend and name the tensor at fault.
class __attribute__((visibility("default"))) RendererPlugin : public Plugin {
 public:
  virtual std::string name() const = 0;
  virtual void forward(const RenderInputs& inputs, RenderOutputs& outputs) = 0;
  // Back-propagates d_image and/or d_shading (nullptr = zero; [N,3,H,W] each) to the targets.
  virtual void backward(const RenderInputs& inputs, const Tensor* d_image,
                        const Tensor* d_shading, const RenderGradients& gradients) = 0;
};

}  // namespace facetool
