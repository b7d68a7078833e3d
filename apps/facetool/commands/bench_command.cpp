// `facetool bench <target>`: performance measurements (today: `ops`, the backend op table).
#include <functional>
#include <iostream>
#include <map>

#include "apps/facetool/bench/op_benchmarks.h"
#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "core/backend/registry.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

struct BenchSettings {
  std::vector<int> batches;
  int repeats = 5;
};

void bench_ops(CommandContext& context, const BenchSettings& settings) {
  Backend& backend = get_backend(context.backend);
  run_op_benchmarks(backend, settings.batches, settings.repeats, std::cout);
}

// Benchmark targets by name; a new one is one more entry.
const std::map<std::string, std::function<void(CommandContext&, const BenchSettings&)>>&
benchmarks() {
  static const std::map<std::string, std::function<void(CommandContext&, const BenchSettings&)>>
      targets = {{"ops", bench_ops}};
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
      ("quick", po::bool_switch(), "a fast smoke run: same as --batches 1 --repeats 3");
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

  if (!values.count("target"))
    throw UsageError("bench needs a target; known benchmarks: " + known_benchmarks());
  const std::string target = values["target"].as<std::string>();
  const auto found = benchmarks().find(target);
  if (found == benchmarks().end())
    throw UsageError("unknown benchmark '" + target + "'; known benchmarks: " +
                     known_benchmarks());

  BenchSettings settings;
  settings.batches = parse_positive_int_list(values["batches"].as<std::string>(), "batches");
  settings.repeats = values["repeats"].as<int>();
  if (settings.repeats < 1)
    throw UsageError("--repeats must be at least 1, got " + std::to_string(settings.repeats));
  if (values["quick"].as<bool>()) {
    settings.batches = {1};
    settings.repeats = 3;
  }
  found->second(context, settings);
  return 0;
}

const CommandRegistration registration{
    {"bench", "measure performance of a backend (bench ops: every op of the op table)",
     run_bench}};

}  // namespace
}  // namespace facetool
