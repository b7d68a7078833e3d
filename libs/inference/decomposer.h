// Decomposer: face crops in, the paper's components out (network, then the renderer).
#pragma once

#include <vector>

#include "core/plugin/network_plugin.h"
#include "core/plugin/renderer_plugin.h"
#include "libs/light/light_from_shading.h"
#include "libs/model/landmark_normals.h"

namespace facetool {

struct NetworkAnswer;  // libs/inference/mirror_average.h

// Host copies of one batch's results, planar per image (NCHW), S = the network's input size.
struct Decomposition {
  int count = 0;
  int size = 0;
  std::vector<float> albedo;          // [N,3,S,S] linear, in [0, 1]
  std::vector<float> normal;          // [N,3,S,S] unit vectors, world frame
  std::vector<float> visibility;      // [N,9,S,S] SH coefficients
  std::vector<float> light;           // [N,27]
  std::vector<float> shading;         // [N,3,S,S] renderer's shading (image = albedo * shading)
  std::vector<float> reconstruction;  // [N,3,S,S] re-rendered image
  // Per crop, the light solved from its shading (Decomposer::set_light_solve); `solved` false
  // where the solve did not run or could not solve the crop (the light is then the network's).
  std::vector<DistantLight> light_solve;
};

class Decomposer {
 public:
  // Both plugins must outlive the decomposer; the network must be built and loaded.
  Decomposer(NetworkPlugin& network, RendererPlugin& renderer);
  // `images`: N crops as planar linear RGB on the host, each followed by the network's input
  // prior when it has one: [N,3+P,S,S] (NetworkPlugin::forward). Runs in eval mode on `backend`.
  // `landmarks` (optional): each crop's 68 landmarks, (x, y) in crop pixels, [N][68][2]; with a
  // landmark normal head (set_landmark_normals) its normals are blended into the network's
  // before rendering, so shading and reconstruction follow them, and the light's gain is fitted
  // (set_light_gain).
  Decomposition run(Backend& backend, const std::vector<float>& images, int count,
                    const std::vector<float>* landmarks = nullptr);
  // Whether each crop runs beside its mirror image, the two answers averaged before rendering
  // (libs/inference/mirror_average.h; on by default: better on every measure of the model card,
  // at twice the network's work). Off: one plain pass, the network's own answer.
  void set_mirror_average(bool on) { mirror_average_ = on; }
  bool mirror_average() const { return mirror_average_; }
  // The weights' landmark normal head (libs/model/landmark_normals.h; null: none), used for
  // the crops run with landmarks. It must outlive the decomposer.
  void set_landmark_normals(const LandmarkNormals* head) { landmark_normals_ = head; }
  const LandmarkNormals* landmark_normals() const { return landmark_normals_; }
  // Whether each colour of the network's light is scaled to render the crop best, in the head's
  // face mask, after rendering (libs/inference/light_gain.h; on by default: the light nearer the
  // truth on synthetic faces and the reconstruction and relighting closer to the photos,
  // docs/photos.md, "The light's gain"). Only crops run with landmarks and a head: the head's
  // mask says where the face is.
  void set_light_gain(bool on) { light_gain_ = on; }
  bool light_gain() const { return light_gain_; }
  // Whether each crop's light is solved from its shading (libs/light/light_from_shading.h: a
  // distant white light plus ambient, then a gain per colour, that makes the renderer explain the face's pixels,
  // robustly), replacing the network's light, and the albedo then follows from the crop and the
  // new shading (bounded where the shading is dark); on by default (docs/photos.md, "The light
  // from the shading"). Like the gain, only crops run with landmarks and a head; the gain then
  // applies only to the crops the solve could not solve.
  void set_light_solve(bool on) { light_solve_ = on; }
  bool light_solve() const { return light_solve_; }
  const NetworkPlugin& network() const { return network_; }

 private:
  // Each crop's light solved from the network's answer (the landmark head's normals blended in)
  // and its crop, in the head's mask (`masks`).
  std::vector<DistantLight> solve_lights(const NetworkAnswer& answer, const std::vector<float>& images, int channels,
                                         const std::vector<std::vector<float>>& masks, int count, int s) const;

  NetworkPlugin& network_;
  RendererPlugin& renderer_;
  bool mirror_average_ = true;
  const LandmarkNormals* landmark_normals_ = nullptr;
  bool light_gain_ = true;
  bool light_solve_ = true;
};

}  // namespace facetool
