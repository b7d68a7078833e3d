// lambertian: a renderer plugin shading SH light without visibility (the SfSNet model), a baseline
// for sh_renderer; its per-pixel work runs as its own OpenCL kernel or the kernel's CPU twin.
#include <cstdint>
#include <string>

#include "core/ops/ops.h"
#include "core/plugin/plugin_api.h"
#include "core/plugin/renderer_plugin.h"
#include "core/util/error.h"
#include "lambertian_kernel.h"

namespace {

using facetool::KernelArg;
using facetool::Shape;
using facetool::Tensor;

KernelArg arg(const Tensor& t) { return KernelArg::of(t); }
KernelArg arg(int64_t v) { return KernelArg::of(static_cast<int32_t>(v)); }

void expect(const Tensor& t, const char* what, const Shape& shape) {
  facetool::check(t.defined() && t.shape() == shape, "lambertian: ", what, " must be ",
                  shape.str(), ", got ", t.defined() ? t.shape().str() : "nothing");
}

class Lambertian final : public facetool::RendererPlugin {
 public:
  std::string name() const override { return "lambertian"; }

  void forward(const facetool::RenderInputs& in, facetool::RenderOutputs& out) override {
    const Shape rgb = check_inputs(in);
    if (!out.image.defined()) out.image = Tensor::empty(in.albedo.backend(), rgb);
    if (!out.shading.defined()) out.shading = Tensor::empty(in.albedo.backend(), rgb);
    expect(out.image, "the output image", rgb);
    expect(out.shading, "the output shading", rgb);
    facetool::ops::launch(lambertian::kernel(), "lambertian_forward", rgb[0] * rgb[2] * rgb[3],
                          {arg(in.albedo), arg(in.normal), arg(in.light), arg(mask_or(in)),
                           arg(out.image), arg(out.shading), arg(int64_t{in.mask.defined()}),
                           arg(rgb[2] * rgb[3])});
  }

  void backward(const facetool::RenderInputs& in, const Tensor* d_image, const Tensor* d_shading,
                const facetool::RenderGradients& g) override {
    const Shape rgb = check_inputs(in);
    if (d_image) expect(*d_image, "d_image", rgb);
    if (d_shading) expect(*d_shading, "d_shading", rgb);
    int64_t flags = (d_image ? 1 : 0) | (d_shading ? 2 : 0);
    if (g.albedo.tensor) flags |= 4 | (g.albedo.accumulate ? 16 : 0);
    if (g.normal.tensor) flags |= 8 | (g.normal.accumulate ? 32 : 0);
    if (g.light.tensor) flags |= g.light.accumulate ? 64 : 0;
    // No visibility in this model: its gradient is zero.
    if (g.visibility.tensor && !g.visibility.accumulate)
      facetool::ops::fill(*g.visibility.tensor, 0.0f);
    const Tensor& none = in.albedo;  // placeholder for absent tensors; their flag is off
    const int64_t pixels = rgb[2] * rgb[3];
    if (g.albedo.tensor || g.normal.tensor) {
      if (g.albedo.tensor) expect(*g.albedo.tensor, "the albedo gradient", rgb);
      if (g.normal.tensor) expect(*g.normal.tensor, "the normal gradient", rgb);
      facetool::ops::launch(lambertian::kernel(), "lambertian_backward", rgb[0] * pixels,
                            {arg(in.albedo), arg(in.normal), arg(in.light), arg(mask_or(in)),
                             arg(d_image ? *d_image : none), arg(d_shading ? *d_shading : none),
                             arg(g.albedo.tensor ? *g.albedo.tensor : none),
                             arg(g.normal.tensor ? *g.normal.tensor : none),
                             arg(int64_t{in.mask.defined()}), arg(pixels), arg(flags)});
    }
    if (g.light.tensor) {
      expect(*g.light.tensor, "the light gradient", Shape{rgb[0], 27});
      facetool::ops::launch(lambertian::kernel(), "lambertian_light", rgb[0] * 27,
                            {arg(in.albedo), arg(in.normal), arg(mask_or(in)),
                             arg(d_image ? *d_image : none), arg(d_shading ? *d_shading : none),
                             arg(*g.light.tensor), arg(int64_t{in.mask.defined()}), arg(pixels),
                             arg(flags)});
    }
  }

 private:
  static const Tensor& mask_or(const facetool::RenderInputs& in) {
    return in.mask.defined() ? in.mask : in.albedo;
  }

  // The image shape [N,3,H,W]; throws for inputs of another shape.
  static Shape check_inputs(const facetool::RenderInputs& in) {
    facetool::check(in.albedo.defined() && in.albedo.shape().rank() == 4 &&
                        in.albedo.shape()[1] == 3,
                    "lambertian: albedo must be [N,3,H,W]");
    const Shape rgb = in.albedo.shape();
    expect(in.normal, "normal", rgb);
    expect(in.light, "light", Shape{rgb[0], 27});
    if (in.mask.defined()) expect(in.mask, "mask", Shape{rgb[0], 1, rgb[2], rgb[3]});
    return rgb;
  }
};

}  // namespace

FACETOOL_DEFINE_PLUGIN(Lambertian, FACETOOL_PLUGIN_RENDERER, "lambertian", "1.0.0",
                       "Lambertian SH shading without visibility (SfSNet's model), own kernel")
