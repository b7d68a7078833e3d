// Shape, backend and value checks of the sh_renderer inputs, with messages naming the tensor.
#include "plugins/sh_renderer/sh_render_checks.h"

#include <climits>
#include <cmath>
#include <vector>

#include "core/backend/backend.h"
#include "core/util/error.h"

namespace facetool::sh_render {

void check_tensor(const char* what, const Tensor& t, const RenderInputs& in, const Shape& shape) {
  check(t.defined(), "sh_renderer: ", what, " is missing; give a ", shape.str(), " tensor");
  check(t.shape() == shape, "sh_renderer: ", what, " must be ", shape.str(), " (albedo is ",
        in.albedo.shape().str(), "), got ", t.shape().str());
  check(&t.backend() == &in.albedo.backend(), "sh_renderer: ", what, " lives on backend '",
        t.backend().name(), "' but albedo on '", in.albedo.backend().name(),
        "'; move all inputs to one backend");
}

RenderSize check_inputs(const RenderInputs& in) {
  check(in.albedo.defined(), "sh_renderer: albedo is missing; give an [N,3,H,W] tensor");
  const Shape& a = in.albedo.shape();
  check(a.rank() == 4 && a[1] == 3, "sh_renderer: albedo must be [N,3,H,W], got ", a.str());
  RenderSize size{a[0], a[2], a[3]};
  check(size.n > 0 && size.pixels() > 0, "sh_renderer: albedo ", a.str(), " is empty");
  // Indices inside the kernel are 32-bit: the largest is 27 * N * H * W (light partials).
  check(27 * size.n * size.pixels() < INT_MAX, "sh_renderer: ", a.str(),
        " is too large for one launch; render fewer or smaller images at a time");
  check_tensor("normal", in.normal, in, Shape{size.n, 3, size.h, size.w});
  check_tensor("visibility", in.visibility, in, Shape{size.n, 9, size.h, size.w});
  check_tensor("light", in.light, in, Shape{size.n, 27});
  if (in.mask.defined()) check_tensor("mask", in.mask, in, Shape{size.n, 1, size.h, size.w});
  return size;
}

void check_light_finite(const Tensor& light) {
  const std::vector<float> values = light.to_host();
  for (size_t k = 0; k < values.size(); ++k)
    check(std::isfinite(values[k]), "sh_renderer: light of image ", k / 27, " has a non-finite ",
          "coefficient ", k % 27, " (", values[k], "); give finite SH coefficients");
}

}  // namespace facetool::sh_render
