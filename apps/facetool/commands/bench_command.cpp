// `facetool bench <target>`: performance measurements: `ops` (the op table), `network`, `render`.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>

#include "apps/facetool/bench/conv_benchmarks.h"
#include "apps/facetool/bench/infer_benchmarks.h"
#include "apps/facetool/bench/network_benchmarks.h"
#include "apps/facetool/bench/op_benchmarks.h"
#include "apps/facetool/bench/render_benchmarks.h"
#include "apps/facetool/bench/train_benchmarks.h"
#include "apps/facetool/bench/photo_benchmarks.h"
#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "libs/model/default_model.h"
#include "libs/photo/photo_outputs.h"
#include "libs/fit/fit_basis.h"
#include "libs/synth/face_model.h"
#include "apps/facetool/infer/network_loading.h"
#include "core/backend/registry.h"
#include "core/util/error.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

struct BenchSettings {
  std::vector<int> batches;
  int repeats = 5;
  bool quick = false;
  int width = 128;
  int input_size = 128;
  int train_batch = 20;
  bool width_given = false;  // --width on the command line (bench train: else 32, 64, 128)
  bool input_size_given = false;  // --input-size on the command line
  std::string photo;
  std::string photos;
  bool save = false;  // bench conv --save
  std::string model;       // bench infer --model (empty: the shipped model)
  std::string face_model;  // bench infer --face-model: for a model with the fit prior
  bool mirror_average = true;  // bench infer: as infer, unless --no-mirror-average
  PhotoOutputs outputs;        // bench infer --outputs: as infer's
};

void bench_ops(CommandContext& context, const BenchSettings& settings) {
  Backend& backend = get_backend(context.backend);
  run_op_benchmarks(backend, settings.batches, settings.repeats, std::cout);
}

// Without --width / --input-size: the shipped model's size (docs/model-card.md: width 32, 96x96),
// then the paper's (width 128, 128x128).
void bench_network(CommandContext& context, const BenchSettings& settings) {
  Backend& backend = get_backend(context.backend);
  check(!settings.save || backend.name() == "cpu", "bench network --save measures the cpu backend's fused ",
        "batch chunk; run it with --backend cpu (the ", backend.name(), " backend chooses its own)");
  std::vector<NetworkConfig> configs;
  if (settings.width_given || settings.input_size_given)
    configs.push_back(NetworkConfig{settings.width, settings.input_size});
  else if (settings.quick)
    configs.push_back(NetworkConfig{32, 96});
  else
    configs = {NetworkConfig{32, 96}, NetworkConfig{128, 128}};
  for (size_t i = 0; i < configs.size(); ++i) {
    if (i > 0) std::cout << "\n";
    auto net = create_plugin<NetworkPlugin>(context, FACETOOL_PLUGIN_NETWORK, "paper_network");
    net->build(backend, configs[i]);
    net->init_random(1);
    NetworkBenchOptions options;
    options.forward_batches = settings.batches;
    options.train_batch = settings.quick ? 2 : settings.train_batch;
    options.repeats = settings.quick ? 1 : settings.repeats;
    options.compare_plain = !settings.quick;
    options.save_chunk = settings.save;
    run_network_benchmarks(*net, backend, net->forward_flops_per_image() / 1e9, options,
                           std::cout);
  }
}

void bench_render(CommandContext& context, const BenchSettings& settings) {
  Backend& backend = get_backend(context.backend);
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, "sh_renderer");
  if (!settings.quick && settings.train_batch < 1)
    throw UsageError("bench render: --train-batch is the render batch and must be at least 1");
  const int batch = settings.quick ? 2 : settings.train_batch;
  run_render_benchmarks(*renderer, backend, batch, settings.input_size, settings.repeats, std::cout);
}

void bench_train(CommandContext& context, const BenchSettings& settings) {
  Backend& backend = get_backend(context.backend);
  TrainBenchOptions options;
  if (settings.width_given || settings.quick) options.widths = {settings.quick ? 8 : settings.width};
  options.input_size = settings.quick ? 32 : settings.input_size;
  options.batch = settings.quick ? 2 : settings.train_batch > 0 ? settings.train_batch : 20;
  options.repeats = settings.quick ? 1 : std::min(settings.repeats, 3);
  run_train_benchmarks(
      [&] { return create_plugin<NetworkPlugin>(context, FACETOOL_PLUGIN_NETWORK, "paper_network"); },
      create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, "sh_renderer"),
      create_plugin<LossPlugin>(context, FACETOOL_PLUGIN_LOSS, "paper_losses"), backend, options,
      std::cout);
}

void bench_photo(CommandContext&, const BenchSettings& settings) {
  run_photo_benchmarks(settings.photo, settings.input_size, settings.quick ? 1 : settings.repeats, std::cout);
}

// The convolution algorithms per layer shape (shipped size unless --width / --input-size).
void bench_conv(CommandContext& context, const BenchSettings& settings) {
  Backend& backend = get_backend(context.backend);
  ConvBenchOptions options;
  if (settings.width_given || settings.input_size_given) {
    options.width = settings.width;
    options.input_size = settings.input_size;
  }
  options.batches = settings.batches;
  options.repeats = settings.repeats;
  options.save = settings.save;
  run_conv_benchmarks(backend, options, std::cout);
}

// Whole photos through infer with --model (default: the shipped model) in its framing, outputs
// written to a temporary folder.
void bench_infer(CommandContext& context, const BenchSettings& settings) {
  namespace fs = std::filesystem;
  Backend& backend = get_backend(context.backend);
  const std::string path = settings.model.empty() ? default_model_path() : settings.model;
  const LoadedNetwork loaded = load_network_weights_file(context, backend, path);
  const std::string& prior = loaded.network->config().input_prior;
  if (!prior.empty() && settings.face_model.empty())
    throw UsageError("bench infer: weights '" + path + "' take the input prior '" + prior +
                     "' (the fit of each face's landmarks, docs/fit.md): give --face-model DIR. " + kIctFaceKitHint);
  const std::shared_ptr<const FitBasis> basis =
      prior.empty() ? nullptr : std::make_shared<const FitBasis>(FitBasis::load(settings.face_model));
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, "sh_renderer");
  Decomposer decomposer(*loaded.network, *renderer);
  decomposer.set_landmark_normals(loaded.landmark_normals.get());
  decomposer.set_mirror_average(settings.mirror_average);
  InferBenchOptions options;
  options.photo.framing = loaded.framing;  // as infer does: crops framed as the model was trained
  options.photo.prior_basis = basis.get();
  options.photo.outputs = settings.outputs;  // as infer --outputs: only those files, only what they need
  options.photo.layers = settings.outputs.layers();
  options.photos = expand_photo_inputs({settings.photos});
  check(!options.photos.empty(), "bench infer: no photos in '", settings.photos, "'");
  options.crop_size = loaded.network->config().input_size;
  options.repeats = settings.quick ? 1 : settings.repeats;
  std::string pattern = (fs::temp_directory_path() / "facetool-bench-infer-XXXXXX").string();
  check(mkdtemp(pattern.data()) != nullptr, "bench infer: cannot create a temporary folder in ",
        fs::temp_directory_path().string());
  options.out_dir = pattern;
  try {
    run_infer_benchmarks(decomposer, backend, options, std::cout);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(options.out_dir, ignored);
    throw;
  }
  std::error_code ignored;
  fs::remove_all(options.out_dir, ignored);
}

// Benchmark targets by name; a new one is one more entry.
const std::map<std::string, std::function<void(CommandContext&, const BenchSettings&)>>&
benchmarks() {
  static const std::map<std::string, std::function<void(CommandContext&, const BenchSettings&)>>
      targets = {{"ops", bench_ops},     {"network", bench_network}, {"render", bench_render},
                 {"train", bench_train}, {"photo", bench_photo},     {"infer", bench_infer},
                 {"conv", bench_conv}};
  return targets;
}

std::string known_benchmarks() {
  std::string names;
  for (const auto& entry : benchmarks()) names += (names.empty() ? "" : ", ") + entry.first;
  return names;
}

int run_bench(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("batches", po::value<std::string>()->default_value("1,20")->value_name("N,N,..."),
       "batch sizes to measure")
      ("repeats", po::value<int>()->default_value(5)->value_name("N"),
       "timed repetitions per measurement (the median is reported)")
      ("quick", po::bool_switch(), "a fast smoke run: batch 1, few repetitions")
      ("width", po::value<int>()->default_value(128),
       "network: width (without it and --input-size: the shipped 32 at 96x96, then the paper's 128 at 128x128)")
      ("input-size", po::value<int>()->default_value(128), "network, render: image size (the paper: 128)")
      ("train-batch", po::value<int>()->default_value(20), "network: batch of the training step (0: skip); render: batch")
      ("photo", po::value<std::string>()->default_value("examples/photos/grace_hopper_512x512.jpg"),
       "photo: a photo with one face (also timed enlarged to 12 megapixels)")
      ("photos", po::value<std::string>()->default_value("examples/photos")->value_name("PHOTO|DIR"),
       "infer: the photos (a folder: its image files), run --repeats times with every output written (or --outputs)")
      ("model", po::value<std::string>()->value_name("WEIGHTS"),
       "infer: network weights (default: the shipped model)")
      ("face-model", po::value<std::string>()->value_name("DIR"),
       "infer: the ICT-FaceKit FaceXModel folder, for weights that take the fit's normals as input")
      ("no-mirror-average", "infer: one network pass per face, as infer --no-mirror-average")
      ("outputs", po::value<std::string>()->value_name("LIST"),
       ("infer: write only these outputs of each photo, as infer --outputs (" + PhotoOutputs::valid_names() +
        "; default all)").c_str())
      ("save", po::bool_switch(),
       "conv: record the fastest algorithm per layer shape in this machine's cache; network: time "
       "the fused forward's batch chunks (one image, the rule's, twice the rule's, the whole batch) and record the "
       "fastest; the fused inference path then uses them (FACETOOL_CONV_CACHE names the file)");
  po::options_description hidden;
  hidden.add_options()("target", po::value<std::string>(), "what to benchmark");
  po::positional_options_description positional;
  positional.add("target", 1);
  po::variables_map values;
  if (!parse_command_options("bench <target> [options]",
                             "Measures performance on the selected backend (--backend). "
                             "Targets: " + known_benchmarks() + ".",
                             options, positional, args, values, hidden))
    return 0;
  check_option_ranges(values, {{"repeats", 1, 10000},
                               {"width", 1, 1024},
                               {"input-size", 2, 1024},
                               {"train-batch", 0, 1024}});

  if (!values.count("target"))
    throw UsageError("bench needs a target; known benchmarks: " + known_benchmarks());
  const std::string target = values["target"].as<std::string>();
  const auto found = benchmarks().find(target);
  if (found == benchmarks().end())
    throw UsageError("unknown benchmark '" + target + "'; known benchmarks: " +
                     known_benchmarks());

  BenchSettings settings;
  settings.batches = parse_positive_int_list(values["batches"].as<std::string>(), "batches");
  for (const int batch : settings.batches)
    if (batch > 1024)
      throw UsageError("--batches: each batch must be in [1, 1024]; got " + std::to_string(batch));
  settings.repeats = values["repeats"].as<int>();
  if (settings.repeats < 1)
    throw UsageError("--repeats must be at least 1, got " + std::to_string(settings.repeats));
  settings.width = values["width"].as<int>();
  settings.width_given = !values["width"].defaulted();
  settings.input_size = values["input-size"].as<int>();
  settings.input_size_given = !values["input-size"].defaulted();
  settings.train_batch = values["train-batch"].as<int>();
  settings.photo = values["photo"].as<std::string>();
  settings.photos = values["photos"].as<std::string>();
  settings.save = values["save"].as<bool>();
  if (values.count("outputs")) {
    if (target != "infer") throw UsageError("--outputs is bench infer's (infer --outputs), not bench " + target + "'s");
    try {
      settings.outputs = PhotoOutputs::parse(values["outputs"].as<std::string>(), "--outputs");
    } catch (const Error& e) {
      throw UsageError("bench infer: " + std::string(e.what()));
    }
  }
  if (values.count("model")) settings.model = values["model"].as<std::string>();
  if (values.count("face-model")) settings.face_model = values["face-model"].as<std::string>();
  settings.mirror_average = values.count("no-mirror-average") == 0;
  if (values["quick"].as<bool>()) {
    settings.quick = true;
    settings.batches = {1};
    settings.repeats = 3;
  }
  found->second(context, settings);
  return 0;
}

const CommandRegistration registration{
    {"bench", "measure performance: bench ops (layer shapes), bench network, bench render, bench train, bench photo, bench infer, bench conv",
     run_bench}};

}  // namespace
}  // namespace facetool
