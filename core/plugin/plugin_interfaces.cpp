// Out-of-line destructors of the plugin interfaces (their type_info lives in the core library)
// and the network input priors.
#include <sstream>

#include "core/plugin/loss_plugin.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/plugin.h"
#include "core/util/error.h"

namespace facetool {

Plugin::~Plugin() = default;
NetworkPlugin::~NetworkPlugin() = default;
LossPlugin::~LossPlugin() = default;

int input_prior_channels(const std::string& prior) {
  if (prior.empty()) return 0;
  if (prior == "fit_normal") return 3;
  // "fit_normal fov F": the fit's perspective camera with F degrees over the crop's width.
  std::istringstream in(prior);
  std::string kind, fov, rest;
  double degrees = 0;
  if (in >> kind >> fov >> degrees && kind == "fit_normal" && fov == "fov" && !(in >> rest) && degrees >= 1 &&
      degrees <= 90)
    return 3;
  throw Error("unknown network input prior '" + prior +
              "': known are none (\"\"), 'fit_normal' and 'fit_normal fov F' (F in [1, 90] degrees)");
}

}  // namespace facetool
