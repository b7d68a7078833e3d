// Loading a decomposition model: the network plugin the weights name, built and loaded, and the
// renderer plugin (for the facetool program and for programs that use facetool as a library).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/backend/backend.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/plugin_loader.h"
#include "core/plugin/renderer_plugin.h"
#include "core/util/error.h"
#include "libs/image/crop_framing.h"
#include "libs/model/landmark_normals.h"

namespace facetool {

// Plugin folders for a program that links libfacetool_core: PluginLoader's defaults
// ($FACETOOL_PLUGIN_PATH, beside the executable, <executable>/../lib/facetool/plugins), then
// libfacetool_core's own folder and <that folder>/facetool/plugins (the install layout).
std::vector<std::string> library_plugin_dirs();

// Creates plugin `name` of `kind` and checks that it implements `Interface`.
template <typename Interface>
std::shared_ptr<Interface> create_plugin_as(PluginLoader& loader, uint32_t kind, const std::string& name) {
  auto plugin = std::dynamic_pointer_cast<Interface>(loader.create(loader.find(kind, name)));
  check(plugin != nullptr, "plugin '", name, "' does not implement the ", plugin_kind_name(kind), " interface");
  return plugin;
}

struct LoadedNetwork {
  std::shared_ptr<NetworkPlugin> network;
  std::string architecture;
  CropFraming framing;  // the weights' framing (v1 for random weights and files without one)
  // The file's landmark normal head (libs/model/landmark_normals.h), or null: give it to the
  // Decomposer (set_landmark_normals) with the crops' landmarks.
  std::shared_ptr<const LandmarkNormals> landmark_normals;
};

// Builds the weights' network on `backend` and loads them. `architecture` (a network plugin's
// name) must agree with the file's when given.
LoadedNetwork load_network_weights_file(PluginLoader& plugins, Backend& backend, const std::string& path,
                                        const std::string& architecture = "");

// Throws facetool::Error naming `weights_path` when the network takes an input prior (the fit's
// normals): for callers that feed crops alone (pseudo-label --model, the Python module); infer
// and relight compute the prior (libs/photo), `facetool eval` reads it from the samples.
void check_takes_photos_alone(const NetworkPlugin& network, const std::string& weights_path);

// A network and a renderer ready for Decomposer (libs/inference/decomposer.h).
struct DecompositionModel {
  std::shared_ptr<NetworkPlugin> network;
  std::shared_ptr<RendererPlugin> renderer;
  std::string architecture;
  std::string weights_path;
  int input_size = 0;  // the crop size the network takes
  CropFraming framing;  // how its crops are framed (the weights' "framing" metadata)
  std::shared_ptr<const LandmarkNormals> landmark_normals;  // the weights' head, or null
};

// Loads `weights_path` (empty: the shipped model, libs/model/default_model.h) and the renderer
// plugin `renderer` on `backend`. Throws facetool::Error naming what is missing.
DecompositionModel load_decomposition_model(PluginLoader& plugins, Backend& backend,
                                            const std::string& weights_path = "",
                                            const std::string& renderer = "sh_renderer");

}  // namespace facetool
