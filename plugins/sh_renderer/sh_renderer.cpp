// The sh_renderer plugin: paper eq. (1) evaluated per pixel with SH triple products.
//
// Forward: one kernel item per pixel writes image and shading (see kernels/sh_render.cl) and a
// per-pixel "normal not finite" flag, summed on the device so the host reads one value.
// Backward: one item per pixel writes the albedo, normal and visibility gradients, and, when the
// light gradient is wanted, the pixel's ds [N,3,H*W] and e [N,9,H*W]. The light gradient
// dL[n,ch,i] = 1/pi sum_p ds[n,ch,p] e[n,i,p] is then reduced in two steps: sh_light_partial
// sums chunks of 256 pixels into [N*27, chunks] partials, and sh_reduce_rows repeatedly sums
// chunks of 256 columns until one is left, the last pass writing (or adding to) the gradient.
#include <algorithm>
#include <map>
#include <mutex>
#include <vector>

#include "core/ops/ops.h"
#include "core/plugin/plugin_api.h"
#include "core/plugin/renderer_plugin.h"
#include "core/sh/triple_product.h"
#include "core/util/error.h"
#include "plugins/sh_renderer/sh_render_checks.h"
#include "plugins/sh_renderer/sh_render_kernel.h"

namespace facetool::sh_render {
namespace {

constexpr int kChunk = 256;

KernelArg arg(const Tensor& t) { return KernelArg::of(t); }
KernelArg arg(int64_t v) { return KernelArg::of(static_cast<int32_t>(v)); }

// Sums each row of src [rows, cols] into dst [rows] (added to it with accumulate).
void reduce_rows(const Tensor& src, int64_t rows, int64_t cols, const Tensor& dst,
                 bool accumulate) {
  Tensor current = src;
  do {
    const int64_t out_cols = (cols + kChunk - 1) / kChunk;
    const bool last = out_cols == 1;
    Tensor out = last ? dst : Tensor::empty(src.backend(), Shape{rows, out_cols});
    ops::launch(kernel(), kReduceRowsEntry, rows * out_cols,
                {arg(current), arg(out), arg(cols), arg(int64_t{kChunk}), arg(out_cols),
                 arg(int64_t{last && accumulate})});
    current = out;
    cols = out_cols;
  } while (cols > 1);
}

class ShRenderer final : public RendererPlugin {
 public:
  std::string name() const override { return "sh_renderer"; }

  void forward(const RenderInputs& in, RenderOutputs& out) override {
    const RenderSize size = check_inputs(in);
    check_light_finite(in.light);
    Backend& backend = in.albedo.backend();
    const Shape rgb{size.n, 3, size.h, size.w};
    if (!out.image.defined()) out.image = Tensor::empty(backend, rgb);
    if (!out.shading.defined()) out.shading = Tensor::empty(backend, rgb);
    check_tensor("output image", out.image, in, rgb);
    check_tensor("output shading", out.shading, in, rgb);
    const int64_t items = size.n * size.pixels();
    Tensor invalid = Tensor::empty(backend, Shape{items});
    const Tensor& table = table_on(backend);
    ops::launch(kernel(), kForwardEntry, items,
                {arg(in.albedo), arg(in.normal), arg(in.visibility), arg(in.light),
                 arg(mask_or(in)), arg(table), arg(out.image), arg(out.shading), arg(invalid),
                 arg(int64_t{in.mask.defined()}), arg(table.shape()[0]), arg(size.pixels())});
    Tensor bad = Tensor::empty(backend, Shape{1});
    reduce_rows(invalid, 1, items, bad, false);
    const float count = bad.to_host()[0];
    check(count == 0.0f, "sh_renderer: ", static_cast<int64_t>(count),
          " rendered pixel(s) have a NaN or infinite normal; fix the normals or mask them out");
  }

  void backward(const RenderInputs& in, const Tensor* d_image, const Tensor* d_shading,
                const RenderGradients& g) override {
    const RenderSize size = check_inputs(in);
    const Shape rgb{size.n, 3, size.h, size.w};
    if (d_image) check_tensor("d_image", *d_image, in, rgb);
    if (d_shading) check_tensor("d_shading", *d_shading, in, rgb);
    if (g.albedo.tensor) check_tensor("albedo gradient", *g.albedo.tensor, in, rgb);
    if (g.normal.tensor) check_tensor("normal gradient", *g.normal.tensor, in, rgb);
    if (g.visibility.tensor)
      check_tensor("visibility gradient", *g.visibility.tensor, in,
                   Shape{size.n, 9, size.h, size.w});
    if (g.light.tensor) check_tensor("light gradient", *g.light.tensor, in, Shape{size.n, 27});
    Backend& backend = in.albedo.backend();
    const int64_t pixels = size.pixels(), items = size.n * pixels;

    int flags = 0;
    if (d_image) flags |= kHasDImage;
    if (d_shading) flags |= kHasDShading;
    if (g.albedo.tensor) flags |= kWantAlbedo | (g.albedo.accumulate ? kAccumulateAlbedo : 0);
    if (g.normal.tensor) flags |= kWantNormal | (g.normal.accumulate ? kAccumulateNormal : 0);
    if (g.visibility.tensor)
      flags |= kWantVisibility | (g.visibility.accumulate ? kAccumulateVisibility : 0);
    if (g.light.tensor) flags |= kWantLight;
    if (!(flags & (kWantAlbedo | kWantNormal | kWantVisibility | kWantLight))) return;

    // Absent tensors are passed as a placeholder the kernel never touches (its flag is off).
    const Tensor& none = in.albedo;
    Tensor ds = none, e = none;
    if (g.light.tensor) {
      ds = Tensor::empty(backend, Shape{size.n, 3, pixels});
      e = Tensor::empty(backend, Shape{size.n, 9, pixels});
    }
    const Tensor& table = table_on(backend);
    ops::launch(kernel(), kBackwardEntry, items,
                {arg(in.albedo), arg(in.normal), arg(in.visibility), arg(in.light),
                 arg(mask_or(in)), arg(table), arg(d_image ? *d_image : none),
                 arg(d_shading ? *d_shading : none),
                 arg(g.albedo.tensor ? *g.albedo.tensor : none),
                 arg(g.normal.tensor ? *g.normal.tensor : none),
                 arg(g.visibility.tensor ? *g.visibility.tensor : none), arg(ds), arg(e),
                 arg(int64_t{in.mask.defined()}), arg(table.shape()[0]), arg(pixels),
                 arg(int64_t{flags})});
    if (!g.light.tensor) return;
    const int64_t rows = size.n * 27, chunks = (pixels + kChunk - 1) / kChunk;
    Tensor partial = Tensor::empty(backend, Shape{rows, chunks});
    ops::launch(kernel(), kLightPartialEntry, rows * chunks,
                {arg(ds), arg(e), arg(partial), arg(pixels), arg(int64_t{kChunk}), arg(chunks)});
    reduce_rows(partial, rows, chunks, g.light.tensor->reshaped(Shape{rows}),
                g.light.accumulate);
  }

 private:
  static const Tensor& mask_or(const RenderInputs& in) {
    return in.mask.defined() ? in.mask : in.albedo;
  }

  // The nonzero T_ijk as (i, j, k, value) rows, uploaded once per backend.
  const Tensor& table_on(Backend& backend) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = tables_.find(&backend);
    if (found != tables_.end()) return found->second;
    const auto& entries = sh::TripleProductTable::get().all_entries();
    std::vector<float> rows;
    for (const sh::TripleEntry& t : entries)
      rows.insert(rows.end(), {static_cast<float>(t.i), static_cast<float>(t.j),
                               static_cast<float>(t.k), static_cast<float>(t.value)});
    const int64_t count = static_cast<int64_t>(entries.size());
    return tables_.emplace(&backend, Tensor::from_host(backend, Shape{count, 4}, rows))
        .first->second;
  }

  std::mutex mutex_;
  std::map<Backend*, Tensor> tables_;
};

}  // namespace
}  // namespace facetool::sh_render

FACETOOL_DEFINE_PLUGIN(facetool::sh_render::ShRenderer, FACETOOL_PLUGIN_RENDERER, "sh_renderer",
                       "1.0.0",
                       "Lambertian SH triple-product renderer (albedo, normal, visibility, light)")
