// ComponentRenderer adapter over RendererPlugin::forward.
#include "libs/synth/plugin_renderer.h"

#include <mutex>

#include "core/plugin/renderer_plugin.h"
#include "core/util/error.h"

namespace facetool {
namespace {

class PluginRenderer : public ComponentRenderer {
 public:
  PluginRenderer(std::shared_ptr<RendererPlugin> plugin, Backend& backend)
      : plugin_(std::move(plugin)), backend_(backend) {
    check(plugin_ != nullptr, "plugin renderer: no plugin given");
  }

  std::string name() const override { return plugin_->name() + " (plugin)"; }

  void render(int pixels, const float* albedo, const float* normal, const float* visibility,
              const sh::RgbLight& light, float* image) const override {
    const int64_t n = pixels;
    RenderInputs inputs;
    inputs.albedo = Tensor::from_host(backend_, Shape{1, 3, 1, n}, {albedo, albedo + 3 * n});
    inputs.normal = Tensor::from_host(backend_, Shape{1, 3, 1, n}, {normal, normal + 3 * n});
    inputs.visibility =
        Tensor::from_host(backend_, Shape{1, 9, 1, n}, {visibility, visibility + 9 * n});
    inputs.light = Tensor::from_host(backend_, Shape{1, 27}, {light.begin(), light.end()});
    RenderOutputs outputs;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      plugin_->forward(inputs, outputs);
    }
    const std::vector<float> result = outputs.image.to_host();
    check(result.size() == static_cast<size_t>(3 * n), "renderer plugin ", plugin_->name(),
          " returned ", result.size(), " values for ", 3 * n);
    std::copy(result.begin(), result.end(), image);
  }

 private:
  std::shared_ptr<RendererPlugin> plugin_;
  Backend& backend_;
  mutable std::mutex mutex_;
};

}  // namespace

std::unique_ptr<ComponentRenderer> make_plugin_renderer(std::shared_ptr<RendererPlugin> plugin,
                                                        Backend& backend) {
  return std::make_unique<PluginRenderer>(std::move(plugin), backend);
}

}  // namespace facetool
