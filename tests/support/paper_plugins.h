// The paper's network and the SH renderer, loaded from their plugin files, for tests of the decomposer.
#pragma once

#include <memory>

#include "core/plugin/network_plugin.h"
#include "core/plugin/plugin_loader.h"
#include "core/plugin/renderer_plugin.h"

namespace facetool::testing {

// Both plugins created from the given files (a test's FACETOOL_PAPER_NETWORK_PLUGIN and
// FACETOOL_SH_RENDERER_PLUGIN); null where a file did not load as that kind.
struct PaperPlugins {
  PluginLoader loader;
  std::shared_ptr<NetworkPlugin> network;
  std::shared_ptr<RendererPlugin> renderer;
  PaperPlugins(const char* network_file, const char* renderer_file) {
    renderer = std::dynamic_pointer_cast<RendererPlugin>(loader.create(loader.load_file(renderer_file)));
    network = std::dynamic_pointer_cast<NetworkPlugin>(loader.create(loader.load_file(network_file)));
  }
};

}  // namespace facetool::testing
