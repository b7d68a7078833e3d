// Out-of-line destructors of the plugin interfaces: their type_info lives in the core library.
#include "core/plugin/loss_plugin.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/plugin.h"

namespace facetool {

Plugin::~Plugin() = default;
NetworkPlugin::~NetworkPlugin() = default;
LossPlugin::~LossPlugin() = default;

}  // namespace facetool
