// Network and renderer plugins from a weights file, and the plugin folders of a library user.
#include "libs/inference/model_loading.h"

#include <algorithm>

#include "libs/model/default_model.h"
#include "libs/model/network_weights.h"
#include "libs/model/safetensors.h"
#include "core/util/shared_library.h"

namespace facetool {

std::vector<std::string> library_plugin_dirs() {
  std::vector<std::string> dirs = PluginLoader::default_search_dirs();
  const std::string core = core_library_dir();
  if (!core.empty())
    for (const std::string& dir : {core, core + "/facetool/plugins"})
      if (std::find(dirs.begin(), dirs.end(), dir) == dirs.end()) dirs.push_back(dir);
  return dirs;
}

LoadedNetwork load_network_weights_file(PluginLoader& plugins, Backend& backend, const std::string& path,
                                        const std::string& architecture) {
  LoadedNetwork out;
  const SafeTensors weights = SafeTensors::read_file(path);
  const WeightsHeader header = read_weights_header(weights, path);
  out.architecture = architecture.empty() ? header.architecture : architecture;
  check(out.architecture == header.architecture, "weights '", path, "' are for network '",
        header.architecture, "' but --network asks for '", out.architecture, "'");
  out.network = create_plugin_as<NetworkPlugin>(plugins, FACETOOL_PLUGIN_NETWORK, out.architecture);
  out.network->build(backend, header.config);
  load_network_weights(*out.network, weights, path);
  out.framing = header.framing;
  out.landmark_normals = read_landmark_normals(weights, path);
  check(!out.landmark_normals || out.landmark_normals->crop_size == header.config.input_size, "weights file '", path,
        "': its landmark normal head was fitted at ", out.landmark_normals ? out.landmark_normals->crop_size : 0,
        " pixels, the network takes ", header.config.input_size);
  return out;
}

void check_takes_photos_alone(const NetworkPlugin& network, const std::string& weights_path) {
  const std::string& prior = network.config().input_prior;
  check(prior.empty(), "weights '", weights_path, "' take the input prior '", prior,
        "' beside the photo (the ICT-FaceKit fit's normals; docs/fit.md), which this path does not compute: ",
        "use `facetool infer --face-model DIR` or `facetool eval` on samples that carry the prior, or a model without one");
}

DecompositionModel load_decomposition_model(PluginLoader& plugins, Backend& backend,
                                            const std::string& weights_path, const std::string& renderer) {
  DecompositionModel model;
  model.weights_path = weights_path.empty() ? default_model_path() : weights_path;
  LoadedNetwork loaded = load_network_weights_file(plugins, backend, model.weights_path);
  check_takes_photos_alone(*loaded.network, model.weights_path);
  model.network = std::move(loaded.network);
  model.architecture = std::move(loaded.architecture);
  model.framing = loaded.framing;
  model.landmark_normals = loaded.landmark_normals;
  model.renderer = create_plugin_as<RendererPlugin>(plugins, FACETOOL_PLUGIN_RENDERER, renderer);
  model.input_size = model.network->config().input_size;
  return model;
}

}  // namespace facetool
