// `facetool bench <target>`: performance measurements: `ops` (the op table), `network`, `render`.
#include <algorithm>
#include <functional>
#include <iostream>
#include <map>

#include "apps/facetool/bench/network_benchmarks.h"
#include "apps/facetool/bench/op_benchmarks.h"
#include "apps/facetool/bench/render_benchmarks.h"
#include "apps/facetool/bench/train_benchmarks.h"
#include "apps/facetool/bench/photo_benchmarks.h"
#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "core/backend/registry.h"

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
  std::string photo;
};

void bench_ops(CommandContext& context, const BenchSettings& settings) {
  Backend& backend = get_backend(context.backend);
  run_op_benchmarks(backend, settings.batches, settings.repeats, std::cout);
}

void bench_network(CommandContext& context, const BenchSettings& settings) {
  Backend& backend = get_backend(context.backend);
  auto net = create_plugin<NetworkPlugin>(context, FACETOOL_PLUGIN_NETWORK, "paper_network");
  net->build(backend, NetworkConfig{settings.width, settings.input_size});
  net->init_random(1);
  NetworkBenchOptions options;
  options.forward_batches = settings.batches;
  options.train_batch = settings.quick ? 2 : settings.train_batch;
  options.repeats = settings.quick ? 1 : settings.repeats;
  run_network_benchmarks(*net, backend, net->forward_flops_per_image() / 1e9, options, std::cout);
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

// Benchmark targets by name; a new one is one more entry.
const std::map<std::string, std::function<void(CommandContext&, const BenchSettings&)>>&
benchmarks() {
  static const std::map<std::string, std::function<void(CommandContext&, const BenchSettings&)>>
      targets = {{"ops", bench_ops}, {"network", bench_network}, {"render", bench_render},
                 {"train", bench_train}, {"photo", bench_photo}};
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
      ("width", po::value<int>()->default_value(128), "network: width (the paper: 128)")
      ("input-size", po::value<int>()->default_value(128), "network, render: image size (the paper: 128)")
      ("train-batch", po::value<int>()->default_value(20), "network: batch of the training step (0: skip); render: batch")
      ("photo", po::value<std::string>()->default_value("examples/photos/grace_hopper_512x512.jpg"),
       "photo: a photo with one face (also timed enlarged to 12 megapixels)");
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
  settings.train_batch = values["train-batch"].as<int>();
  settings.photo = values["photo"].as<std::string>();
  if (values["quick"].as<bool>()) {
    settings.quick = true;
    settings.batches = {1};
    settings.repeats = 3;
  }
  found->second(context, settings);
  return 0;
}

const CommandRegistration registration{
    {"bench", "measure performance: bench ops (layer shapes), bench network, bench render, bench train, bench photo",
     run_bench}};

}  // namespace
}  // namespace facetool
