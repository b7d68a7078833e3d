// The loss-term plugin interface: named differentiable scalar terms of network outputs and targets.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/autograd/variable.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/plugin.h"
#include "core/plugin/renderer_plugin.h"

namespace facetool {

// What a term reads from the batch besides the prediction. A data source that lacks one of
// these (real photos without pseudo labels) cannot feed the term; training configurations are
// checked against this before the first step.
enum LossNeeds : uint32_t {
  kNeedsImage = 1u << 0,
  kNeedsAlbedo = 1u << 1,
  kNeedsNormal = 1u << 2,
  kNeedsVisibility = 1u << 3,
  kNeedsLight = 1u << 4,
};

// The batch a term compares against, on the predictions' backend. N images of H x W pixels in
// the layouts of RenderInputs; tensors the data source lacks are left undefined.
struct LossTargets {
  Tensor image;       // [N,3,H,W] the input photo (linear RGB)
  Tensor albedo;      // [N,3,H,W]
  Tensor normal;      // [N,3,H,W] unit
  Tensor visibility;  // [N,9,H,W]
  Tensor light;       // [N,27]
  Tensor mask;        // [N,1,H,W] the face mask eroded by one pixel: where every term is counted
};

struct LossTermInfo {
  std::string name;         // unique among loaded loss plugins, e.g. "recon_albedo"
  std::string description;  // one line, e.g. "E_recon-rho: predicted albedo, other parts targets"
  uint32_t needs = 0;       // LossNeeds bits
};

// A loss plugin (kind FACETOOL_PLUGIN_LOSS) provides one or more terms. evaluate() returns a
// differentiable scalar ([1]) built from core/autograd functions (and the renderer through
// core/plugin/renderer_autograd.h), so that backward() on a weighted sum of terms reaches the
// network. Implementations throw facetool::Error for an unknown term or a missing target.
class __attribute__((visibility("default"))) LossPlugin : public Plugin {
 public:
  ~LossPlugin() override;
  virtual std::vector<LossTermInfo> terms() const = 0;
  // The renderer must outlive the returned graph.
  virtual ag::Variable evaluate(const std::string& term, const NetworkOutputs& predicted,
                                const LossTargets& targets, RendererPlugin& renderer) = 0;
};

}  // namespace facetool
