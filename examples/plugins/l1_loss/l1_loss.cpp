// l1_loss: a loss plugin with two L1 terms over the face mask, built from autograd functions only:
//   l1_albedo  mean |predicted albedo - target albedo|
//   l1_recon   mean |render(predicted albedo, normal, visibility, light) - input image|
// (mean over masked pixels and the 3 channels; |x| = leaky_relu(x, -1)).
#include <string>
#include <vector>

#include "core/autograd/functions.h"
#include "core/plugin/loss_plugin.h"
#include "core/plugin/plugin_api.h"
#include "core/plugin/renderer_autograd.h"
#include "core/util/error.h"

namespace {

namespace ag = facetool::ag;
using facetool::Tensor;

// mean over the masked pixels and channels of |a - b|; a, b [N,3,H,W], mask [N,1,H,W].
ag::Variable masked_l1(const ag::Variable& a, const ag::Variable& b, const Tensor& mask) {
  facetool::check(mask.defined(), "l1_loss: the batch has no face mask");
  const ag::Variable difference = ag::add(a, ag::scale(b, -1.0f));
  const ag::Variable m(mask);
  const ag::Variable masked =
      ag::mul(ag::leaky_relu(difference, -1.0f), ag::concat_channels({m, m, m}));
  double count = 0;
  for (float v : mask.to_host()) count += v;
  facetool::check(count > 0, "l1_loss: the face mask is empty");
  return ag::scale(ag::sum(masked), static_cast<float>(1.0 / (3.0 * count)));
}

class L1Loss final : public facetool::LossPlugin {
 public:
  std::vector<facetool::LossTermInfo> terms() const override {
    return {{"l1_albedo", "mean |albedo - target albedo| over the face mask",
             facetool::kNeedsAlbedo},
            {"l1_recon", "mean |rendered image - input image| over the face mask",
             facetool::kNeedsImage}};
  }

  ag::Variable evaluate(const std::string& term, const facetool::NetworkOutputs& predicted,
                        const facetool::LossTargets& targets,
                        facetool::RendererPlugin& renderer) override {
    if (term == "l1_albedo")
      return masked_l1(predicted.albedo, ag::Variable(targets.albedo), targets.mask);
    if (term == "l1_recon") {
      const ag::Variable image = facetool::render_image(
          renderer, predicted.albedo, predicted.normal, predicted.visibility, predicted.light);
      return masked_l1(image, ag::Variable(targets.image), targets.mask);
    }
    facetool::fail("l1_loss: unknown term '", term, "'; terms: l1_albedo, l1_recon");
  }
};

}  // namespace

FACETOOL_DEFINE_PLUGIN(L1Loss, FACETOOL_PLUGIN_LOSS, "l1_loss", "1.0.0",
                       "L1 terms: l1_albedo and l1_recon (mean absolute error over the face mask)")
