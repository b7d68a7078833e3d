// Out-of-line destructors of the plugin interfaces (their type_info lives in the core library)
// and the network input priors.
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
  throw Error("unknown network input prior '" + prior + "': known are none (\"\") and 'fit_normal'");
}

}  // namespace facetool
