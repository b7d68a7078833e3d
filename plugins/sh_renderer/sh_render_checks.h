// Input validation of the sh_renderer: shapes, backends, sizes, finite lights.
#pragma once

#include <cstdint>

#include "core/plugin/renderer_plugin.h"

namespace facetool::sh_render {

struct RenderSize {
  int64_t n = 0, h = 0, w = 0;
  int64_t pixels() const { return h * w; }
};

// Checks every input tensor (and the mask when present) and returns N, H, W; throws
// facetool::Error naming the tensor at fault and the expected shape.
RenderSize check_inputs(const RenderInputs& in);
// Checks that `t` is defined, on the inputs' backend and of `shape`.
void check_tensor(const char* what, const Tensor& t, const RenderInputs& in, const Shape& shape);
// Fails if the light holds NaN or infinity (downloads the N x 27 values).
void check_light_finite(const Tensor& light);

}  // namespace facetool::sh_render
