// Decomposer: one eval-mode network pass (optionally beside the mirrored batch), the landmark normal head, one render per batch, the light's gain.
#include "libs/inference/decomposer.h"

#include <array>
#include <optional>
#include <utility>

#include "core/backend/backend.h"
#include "core/util/error.h"
#include "core/util/stage_timer.h"
#include "libs/inference/albedo_from_shading.h"
#include "libs/inference/light_gain.h"
#include "libs/inference/mirror_average.h"

namespace facetool {

Decomposer::Decomposer(NetworkPlugin& network, RendererPlugin& renderer)
    : network_(network), renderer_(renderer) {}

std::vector<DistantLight> Decomposer::solve_lights(const NetworkAnswer& answer, const std::vector<float>& images,
                                                   int channels, const std::vector<std::vector<float>>& masks,
                                                   int count, int s) const {
  const size_t plane = static_cast<size_t>(s) * s;
  std::vector<DistantLight> solves(count);
  for (int i = 0; i < count; ++i) {
    ShadingInputs in;
    in.image = images.data() + static_cast<size_t>(i) * channels * plane;
    in.albedo = answer.albedo.data() + i * 3 * plane;
    in.normal = answer.normal.data() + i * 3 * plane;
    in.visibility = answer.visibility.data() + i * 9 * plane;
    in.mask = masks[i].data();
    in.size = s;
    solves[i] = solve_distant_light(in);
  }
  return solves;
}

Decomposition Decomposer::run(Backend& backend, const std::vector<float>& images, int count,
                              const std::vector<float>* landmarks) {
  const int s = network_.config().input_size;
  const int channels = 3 + input_prior_channels(network_.config().input_prior);
  check(count > 0 && images.size() == static_cast<size_t>(count) * channels * s * s,
        "decomposer: expected ", count, " images of ", channels, "x", s, "x", s, " values");
  constexpr size_t kPoints = 2 * LandmarkNormals::kLandmarks;
  check(!landmarks || landmarks->size() == static_cast<size_t>(count) * kPoints, "decomposer: expected the ",
        kPoints, " landmark coordinates of each of ", count, " crops, got ", landmarks ? landmarks->size() : 0);
  std::optional<StageTimer> timer(std::in_place, "network");
  const int prior_normal = channels > 3 ? 3 : -1;  // the input prior is a normal map
  const int batch = mirror_average_ ? 2 * count : count;
  ag::Variable input(Tensor::from_host(
      backend, Shape{batch, channels, s, s},
      mirror_average_ ? with_mirror_images(images, count, channels, s, prior_normal) : images));
  NetworkOutputs out = network_.forward(input, false);
  backend.synchronize();
  // The host copies the decomposition returns: the network's own answer, or the average.
  NetworkAnswer answer{out.albedo.value().to_host(), out.normal.value().to_host(),
                       out.visibility.value().to_host(), out.light.value().to_host()};
  Tensor albedo = out.albedo.value(), normal = out.normal.value();
  Tensor visibility = out.visibility.value(), light = out.light.value();
  if (mirror_average_) {
    answer = average_with_mirror(answer, count, s);
    albedo = Tensor::from_host(backend, Shape{count, 3, s, s}, answer.albedo);
    normal = Tensor::from_host(backend, Shape{count, 3, s, s}, answer.normal);
    visibility = Tensor::from_host(backend, Shape{count, 9, s, s}, answer.visibility);
    light = Tensor::from_host(backend, Shape{count, 27}, answer.light);
  }
  const size_t plane = static_cast<size_t>(s) * s;
  std::vector<std::vector<float>> head_masks;  // the head's face mask of each crop
  if (landmark_normals_ && landmarks) {
    check(landmark_normals_->crop_size == s, "decomposer: the landmark normal head was fitted at ",
          landmark_normals_->crop_size, " pixels, the network takes ", s);
    head_masks.resize(count);
    for (int i = 0; i < count; ++i)
      landmark_normals_->blend_into(landmarks->data() + i * kPoints, answer.normal.data() + i * 3 * plane,
                                    &head_masks[i]);
    normal = Tensor::from_host(backend, Shape{count, 3, s, s}, answer.normal);
  }
  // Each crop's light solved from its shading, in place of the network's, before the one render.
  std::vector<DistantLight> solves(count);
  if (light_solve_ && !head_masks.empty()) {
    timer.emplace("light solve");
    solves = solve_lights(answer, images, channels, head_masks, count, s);
    bool any = false;
    for (int i = 0; i < count; ++i) {
      if (!solves[i].solved) continue;
      const sh::RgbLight solved = sh_light(solves[i]);
      for (int k = 0; k < 27; ++k) answer.light[i * 27 + k] = static_cast<float>(solved[k]);
      any = true;
    }
    if (any) light = Tensor::from_host(backend, Shape{count, 27}, answer.light);
  }
  timer.emplace("render");
  RenderInputs render_in{albedo, normal, visibility, light, Tensor()};
  RenderOutputs render_out;
  renderer_.forward(render_in, render_out);

  Decomposition d;
  d.count = count;
  d.size = s;
  d.albedo = std::move(answer.albedo);
  d.normal = std::move(answer.normal);
  d.visibility = std::move(answer.visibility);
  d.light = std::move(answer.light);
  d.shading = render_out.shading.to_host();
  d.reconstruction = render_out.image.to_host();
  d.light_solve = std::move(solves);
  // A solved crop's albedo follows from the crop and its new shading, and its reconstruction
  // from both; the others keep the network's light, scaled by the light's gain.
  timer.emplace("light solve");
  for (int i = 0; i < count; ++i) {
    if (!d.light_solve[i].solved) continue;
    const size_t at = i * 3 * plane;
    albedo_from_shading(images.data() + static_cast<size_t>(i) * channels * plane, d.shading.data() + at,
                        head_masks[i].data(), plane, d.albedo.data() + at);
    for (size_t k = 0; k < 3 * plane; ++k) d.reconstruction[at + k] = d.albedo[at + k] * d.shading[at + k];
  }
  if (light_gain_ && !head_masks.empty()) {
    timer.emplace("light gain");
    for (int i = 0; i < count; ++i) {
      if (d.light_solve[i].solved) continue;
      const std::array<float, 3> gain = fit_light_gain(d.reconstruction.data() + i * 3 * plane,
                                                       images.data() + static_cast<size_t>(i) * channels * plane,
                                                       head_masks[i].data(), plane);
      apply_light_gain(gain, d.light.data() + i * 27, d.shading.data() + i * 3 * plane,
                       d.reconstruction.data() + i * 3 * plane, plane);
    }
  }
  return d;
}

}  // namespace facetool
