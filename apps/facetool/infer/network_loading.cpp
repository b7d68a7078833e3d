// The network options shared by `infer` and `relight` (--model W, default the shipped model, or --init random), --no-mirror-average, --no-landmark-normals, --no-light-gain and --no-light-solve.
#include "apps/facetool/infer/network_loading.h"

#include "libs/model/default_model.h"

namespace po = boost::program_options;

namespace facetool {

void add_network_options(po::options_description& options) {
  options.add_options()
      ("model,m", po::value<std::string>()->value_name("WEIGHTS"),
       "network weights (.safetensors, docs/model-format.md; default: the shipped model "
       "share/facetool/models/facetool-v2.safetensors, docs/model-card.md)")
      ("init", po::value<std::string>(), "'random': untrained weights instead of --model (for testing the pipeline)")
      ("seed", po::value<uint64_t>()->default_value(1), "seed of --init random")
      ("width", po::value<int>()->default_value(128), "network width for --init random")
      ("input-size", po::value<int>()->default_value(128), "network input size for --init random")
      ("network", po::value<std::string>(), "network plugin (default: the weights' architecture, else paper_network)")
      ("face-model", po::value<std::string>()->value_name("DIR"),
       "the ICT-FaceKit FaceXModel folder: for a model that takes the fit's normals as input (docs/fit.md), and infer --with-fit");
  add_mirror_average_option(options);
  add_landmark_head_options(options);
}

void add_mirror_average_option(po::options_description& options) {
  options.add_options()
      ("no-mirror-average", "one network pass per face crop: without it each crop runs beside its mirror image and the "
       "two answers are averaged (half the network's time; docs/photos.md, \"Mirror averaging\")");
}

void apply_mirror_average_option(const po::variables_map& values, Decomposer& decomposer) {
  decomposer.set_mirror_average(values.count("no-mirror-average") == 0);
}

void add_landmark_head_options(po::options_description& options) {
  options.add_options()
      ("no-landmark-normals", "the network's normals alone: without it, weights that carry a landmark normal head "
       "(the shipped model does) blend its normals, predicted from each face's landmarks, into the network's "
       "(docs/model-card.md, \"The landmark normal head\"); also leaves the light's gain out")
      ("no-light-gain", "the network's light as it is: without it, each colour of the light is scaled to render the "
       "face best in the landmark normal head's face mask (docs/photos.md, \"The light's gain\")")
      ("no-light-solve", "the network's light (with its gain): without it, each face's light is solved from its shading, "
       "a distant light plus ambient that makes the renderer explain the face's pixels, and the albedo follows from "
       "the photo and that shading (docs/photos.md, \"The light from the shading\")");
}

void apply_landmark_head_options(const po::variables_map& values, Decomposer& decomposer,
                                 const LoadedNetwork& loaded) {
  decomposer.set_landmark_normals(values.count("no-landmark-normals") ? nullptr : loaded.landmark_normals.get());
  decomposer.set_light_gain(values.count("no-light-gain") == 0);
  decomposer.set_light_solve(values.count("no-light-solve") == 0);
}

std::vector<OptionRange> network_option_ranges() {
  return {{"seed", 0, 18446744073709551615.0}, {"width", 1, 1024}, {"input-size", 2, 1024}};
}

void check_network_choice(const po::variables_map& values, const std::string& command) {
  if (values.count("model") && values.count("init"))
    throw UsageError(command + ": give --model WEIGHTS or --init random, not both");
  if (values.count("init") && values["init"].as<std::string>() != "random")
    throw UsageError(command + ": --init takes only 'random'");
}

LoadedNetwork load_network_weights_file(CommandContext& context, Backend& backend,
                                        const std::string& path, const std::string& architecture) {
  return load_network_weights_file(context.plugins(), backend, path, architecture);
}

LoadedNetwork load_network(CommandContext& context, const po::variables_map& values, Backend& backend) {
  LoadedNetwork out;
  out.architecture = values.count("network") ? values["network"].as<std::string>() : "";
  if (!values.count("init")) {
    const std::string path =
        values.count("model") ? values["model"].as<std::string>() : default_model_path();
    out = load_network_weights_file(context, backend, path, out.architecture);
    const std::string& prior = out.network->config().input_prior;
    if (!prior.empty() && !values.count("face-model"))
      throw UsageError("weights '" + path + "' take the input prior '" + prior + "' (the fit of each face's landmarks, " +
                       "docs/fit.md): give --face-model DIR. " + kIctFaceKitHint);
  } else {
    if (out.architecture.empty()) out.architecture = "paper_network";
    out.network = create_plugin<NetworkPlugin>(context, FACETOOL_PLUGIN_NETWORK, out.architecture);
    out.network->build(backend, NetworkConfig{values["width"].as<int>(), values["input-size"].as<int>()});
    out.network->init_random(values["seed"].as<uint64_t>());
  }
  return out;
}

std::shared_ptr<const FitBasis> load_face_model(const po::variables_map& values, const LoadedNetwork& loaded) {
  const bool wanted = values.count("with-fit") || !loaded.network->config().input_prior.empty();
  if (!wanted || !values.count("face-model")) return nullptr;
  return std::make_shared<const FitBasis>(FitBasis::load(values["face-model"].as<std::string>()));
}

}  // namespace facetool
