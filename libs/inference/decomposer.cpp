// Decomposer: one eval-mode network pass and one render per batch.
#include "libs/inference/decomposer.h"

#include <optional>

#include "core/backend/backend.h"
#include "core/util/error.h"
#include "core/util/stage_timer.h"

namespace facetool {

Decomposer::Decomposer(NetworkPlugin& network, RendererPlugin& renderer)
    : network_(network), renderer_(renderer) {}

Decomposition Decomposer::run(Backend& backend, const std::vector<float>& images, int count) {
  const int s = network_.config().input_size;
  const int channels = 3 + input_prior_channels(network_.config().input_prior);
  check(count > 0 && images.size() == static_cast<size_t>(count) * channels * s * s,
        "decomposer: expected ", count, " images of ", channels, "x", s, "x", s, " values");
  std::optional<StageTimer> timer(std::in_place, "network");
  ag::Variable input(Tensor::from_host(backend, Shape{count, channels, s, s}, images));
  NetworkOutputs out = network_.forward(input, false);
  backend.synchronize();
  timer.emplace("render");
  RenderInputs render_in{out.albedo.value(), out.normal.value(), out.visibility.value(),
                         out.light.value(), Tensor()};
  RenderOutputs render_out;
  renderer_.forward(render_in, render_out);

  Decomposition d;
  d.count = count;
  d.size = s;
  d.albedo = out.albedo.value().to_host();
  d.normal = out.normal.value().to_host();
  d.visibility = out.visibility.value().to_host();
  d.light = out.light.value().to_host();
  d.shading = render_out.shading.to_host();
  d.reconstruction = render_out.image.to_host();
  return d;
}

}  // namespace facetool
