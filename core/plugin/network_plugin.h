// NetworkPlugin: the interface of network plugins (image in; albedo, normal, visibility, light out).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/autograd/variable.h"
#include "core/plugin/plugin.h"

namespace facetool {

// Architecture hyper-parameters, stored with the weights (safetensors metadata).
struct NetworkConfig {
  int width = 128;       // channels of the 64x64 trunk (the paper: 128); other layers scale with it
  int input_size = 128;  // square input resolution (the paper: 128); must be divisible by 2
  // What the network receives besides the image: "" (the paper: nothing) or "fit_normal" (the
  // normals of the ICT-FaceKit fit to the face's landmarks, 3 more input channels, 0 where the
  // fitted face does not cover the crop; docs/fit.md "The fit as the network's input"), the fit's
  // camera at its default field of view, or "fit_normal fov F" at F degrees over the crop.
  std::string input_prior = "";
};

// Input channels the prior adds (0 for "", 3 for "fit_normal" and "fit_normal fov F"); throws
// facetool::Error naming `prior` and the known ones otherwise.
int input_prior_channels(const std::string& prior);

// Per image: albedo [N,3,S,S] in [0,1], unit normal [N,3,S,S], visibility SH [N,9,S,S],
// light SH [N,27] (9 per RGB channel, channel-major).
struct NetworkOutputs {
  ag::Variable albedo;
  ag::Variable normal;
  ag::Variable visibility;
  ag::Variable light;
};

class NetworkPlugin : public Plugin {
 public:
  ~NetworkPlugin() override;
  // Creates the parameters and state for `config` on `backend` (values uninitialised).
  virtual void build(Backend& backend, const NetworkConfig& config) = 0;
  virtual const NetworkConfig& config() const = 0;
  // Every learnable parameter with its stable name (the safetensors key), in a fixed order.
  virtual std::vector<std::pair<std::string, ag::Variable>> parameters() const = 0;
  // Non-learnable state (batch-norm running statistics) with its names.
  virtual std::vector<std::pair<std::string, Tensor>> buffers() const = 0;
  // Reproducible initial weights: Kaiming-normal convolutions, unit/zero batch norms.
  virtual void init_random(uint64_t seed) = 0;
  // images [N,3+P,S,S]: RGB in [0,1], then the P = input_prior_channels(config().input_prior)
  // prior channels. `training` selects batch statistics in batch norm (and updates the running
  // ones).
  virtual NetworkOutputs forward(const ag::Variable& images, bool training) = 0;
  // Multiply-adds x 2 of one image's forward pass (for benchmarks); 0 when unknown.
  virtual double forward_flops_per_image() const { return 0.0; }
};

}  // namespace facetool
