// The paper_losses plugin: the paper's supervised, light and reconstruction terms (section 4.3).
//
// Every image term is a masked mean squared error over the eroded face mask (ops::masked_mse:
// sum over masked pixels and channels / (channels x masked pixels)). Reconstruction terms
// compare the input image with the sh_renderer's image of a mix of predicted and target parts.
#include <functional>
#include <map>

#include "core/autograd/functions.h"
#include "core/plugin/loss_plugin.h"
#include "core/plugin/plugin_api.h"
#include "core/plugin/renderer_autograd.h"
#include "core/util/error.h"
#include "plugins/paper_losses/light_loss.h"

namespace facetool::paper_losses {
namespace {

// One component of the render: the prediction, or the target as a constant.
enum Source { kPredicted, kTarget, kPredictedBlocked };

struct Term {
  LossTermInfo info;
  // For reconstruction terms: where albedo, normal, visibility and light come from.
  bool reconstruction = false;
  Source parts[4] = {kTarget, kTarget, kTarget, kTarget};
  // For supervised terms: the component compared (0 albedo, 1 normal, 2 visibility, 3 light).
  int component = -1;
};

constexpr uint32_t kAllTargets = kNeedsAlbedo | kNeedsNormal | kNeedsVisibility | kNeedsLight;
const char* const kComponentNames[4] = {"albedo", "normal", "visibility", "light"};
const uint32_t kComponentNeeds[4] = {kNeedsAlbedo, kNeedsNormal, kNeedsVisibility, kNeedsLight};

std::vector<Term> make_terms() {
  std::vector<Term> terms;
  const char* symbols[4] = {"rho", "n", "v", "L"};
  for (int c = 0; c < 4; ++c) {
    Term t;
    t.info = {kComponentNames[c],
              std::string("E_") + symbols[c] + (c == 3 ? ": light values over 64,000 directions"
                                                       : ": masked MSE against the target"),
              kComponentNeeds[c]};
    t.component = c;
    terms.push_back(t);
  }
  for (int c = 0; c < 4; ++c) {
    Term t;
    t.info = {std::string("recon_") + kComponentNames[c],
              std::string("E_recon-") + symbols[c] + ": predicted " + kComponentNames[c] +
                  ", the other parts from the targets",
              kNeedsImage | (kAllTargets & ~kComponentNeeds[c])};
    t.reconstruction = true;
    t.parts[c] = kPredicted;
    terms.push_back(t);
  }
  Term three;
  three.info = {"recon_albedo_normal_light",
                "E_recon-rho,n,L: every part predicted, visibility's gradient blocked",
                kNeedsImage};
  three.reconstruction = true;
  three.parts[0] = three.parts[1] = three.parts[3] = kPredicted;
  three.parts[2] = kPredictedBlocked;
  terms.push_back(three);
  Term four;
  four.info = {"recon_all", "E_recon-rho,n,v,L: every part predicted (for experiments)",
               kNeedsImage};
  four.reconstruction = true;
  for (Source& s : four.parts) s = kPredicted;
  terms.push_back(four);
  return terms;
}

const Tensor& target_of(const LossTargets& t, int component) {
  const Tensor* all[4] = {&t.albedo, &t.normal, &t.visibility, &t.light};
  return *all[component];
}

const ag::Variable& predicted_of(const NetworkOutputs& p, int component) {
  const ag::Variable* all[4] = {&p.albedo, &p.normal, &p.visibility, &p.light};
  return *all[component];
}

class PaperLosses final : public LossPlugin {
 public:
  PaperLosses() : terms_(make_terms()) {}

  std::vector<LossTermInfo> terms() const override {
    std::vector<LossTermInfo> out;
    for (const Term& t : terms_) out.push_back(t.info);
    return out;
  }

  ag::Variable evaluate(const std::string& name, const NetworkOutputs& predicted,
                        const LossTargets& targets, RendererPlugin& renderer) override {
    const Term* term = nullptr;
    for (const Term& t : terms_)
      if (t.info.name == name) term = &t;
    check(term != nullptr, "paper_losses: no term called '", name, "'");
    check(targets.mask.defined(), "paper_losses: term '", name, "' needs the batch's mask");
    for (int c = 0; c < 4; ++c)
      if (term->info.needs & kComponentNeeds[c])
        check(target_of(targets, c).defined(), "paper_losses: term '", name, "' needs the target ",
              kComponentNames[c], ", which this batch lacks (real photos need pseudo labels: "
              "facetool pseudo-label)");
    if (term->info.needs & kNeedsImage)
      check(targets.image.defined(), "paper_losses: term '", name, "' needs the input image");

    if (!term->reconstruction) {
      const ag::Variable& p = predicted_of(predicted, term->component);
      check(p.defined(), "paper_losses: the network gave no ", kComponentNames[term->component]);
      const ag::Variable t(target_of(targets, term->component));
      if (term->component == 3) return light_loss(p, t);
      return ag::masked_mse(p, t, targets.mask);
    }
    ag::Variable parts[4];
    for (int c = 0; c < 4; ++c) {
      switch (term->parts[c]) {
        case kTarget: parts[c] = ag::Variable(target_of(targets, c)); break;
        case kPredicted: parts[c] = predicted_of(predicted, c); break;
        case kPredictedBlocked: parts[c] = ag::stop_gradient(predicted_of(predicted, c)); break;
      }
      check(parts[c].defined(), "paper_losses: the network gave no ", kComponentNames[c]);
    }
    const ag::Variable image =
        render_image(renderer, parts[0], parts[1], parts[2], parts[3], targets.mask);
    return ag::masked_mse(image, ag::Variable(targets.image), targets.mask);
  }

 private:
  std::vector<Term> terms_;
};

}  // namespace
}  // namespace facetool::paper_losses

FACETOOL_DEFINE_PLUGIN(facetool::paper_losses::PaperLosses, FACETOOL_PLUGIN_LOSS, "paper_losses",
                       "1.0.0",
                       "Zhong et al.'s loss terms: supervised albedo/normal/visibility/light and "
                       "univariate, three- and four-variate reconstructions")
