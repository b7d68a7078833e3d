// `facetool train`: runs one training stage from a configuration file into a run folder (TrainingRun).
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "core/backend/registry.h"
#include "libs/distributed/communicator.h"
#include "libs/train/trainer.h"
#include "core/util/memory_budget.h"
#include "libs/train/training_run.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;

namespace facetool {
namespace {


std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int signal) { g_stop_signal.store(signal); }

int run_train_command(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string config_path, out, from;
  int64_t steps = 0;
  double time_limit_minutes = 0;
  options.add_options()
      ("config", po::value(&config_path)->value_name("FILE.json")->required(),
       "training configuration (configs/*.json; docs/training.md)")
      ("out,o", po::value(&out)->value_name("RUN")->required(),
       "run folder: checkpoint.safetensors, weights.safetensors, log.jsonl, loss.png")
      ("init", po::value<std::string>()->value_name("random")->default_value("random"),
       "initial weights: random (seeded by the configuration's seed)")
      ("from", po::value(&from)->value_name("WEIGHTS"),
       "start from these weights (a weights file or a checkpoint), e.g. stage 1's for stage 2")
      ("steps", po::value(&steps)->value_name("N"), "train N steps in all (default: the config's)")
      ("time-limit", po::value(&time_limit_minutes)->value_name("MINUTES"),
       "stop after this much wall time in this process (checkpoint written; --resume continues): "
       "runs of equal time, sittings of a long run")
      ("resume", "continue the run in RUN from its checkpoint, exactly (same losses on cpu)")
      ("overwrite", "start afresh in a RUN that holds another run's weights or log (without a "
       "checkpoint to resume): they are replaced");
  po::variables_map values;
  if (!parse_command_options(
          "train --config FILE.json --out RUN [options]",
          "Trains the network for one stage of the paper (or any configuration), with the loss "
          "terms of the loaded loss plugins. Writes a checkpoint every checkpoint_every steps, on "
          "Ctrl-C / SIGTERM / SIGHUP and at the end; --resume continues from it. Under mpirun -np "
          "K the ranks split every batch\n(data-parallel; docs/distributed.md) and rank 0 writes "
          "the run folder.",
          options, {}, args, values))
    return 0;
  check_option_ranges(values, {{"steps", 1, 1e9}, {"time-limit", 0.01, 1e6}});
  if (values["init"].as<std::string>() != "random")
    throw UsageError("--init takes only 'random'; use --from WEIGHTS for a weights file");
  const bool resume = values.count("resume") != 0;
  if (resume && !from.empty()) throw UsageError("--resume and --from exclude each other");

  TrainingConfig config = read_training_config(config_path);
  if (values.count("steps")) {
    if (steps < 1) throw UsageError("--steps must be >= 1");
    config.steps = steps;
  }
  Backend& backend = get_backend(context.backend);
  auto network = create_plugin<NetworkPlugin>(context, FACETOOL_PLUGIN_NETWORK, config.network);
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, config.renderer);
  std::vector<std::shared_ptr<LossPlugin>> losses;
  for (const PluginInfo& info : context.plugins().plugins())
    if (info.kind == FACETOOL_PLUGIN_LOSS)
      losses.push_back(create_plugin<LossPlugin>(context, FACETOOL_PLUGIN_LOSS, info.name));
  check(!losses.empty(), "no loss plugin found (paper_losses.ftplugin.so); see `facetool plugins`");
  // Building the network allocates its parameters, their gradients and Adam's moments.
  const int64_t parameters = Trainer::parameter_estimate(config);
  std::optional<Trainer> built;
  char millions[32];
  std::snprintf(millions, sizeof millions, "%.1f", static_cast<double>(parameters) / 1e6);
  naming_out_of_memory("building the " + config.network + " of width " +
                           std::to_string(config.width) + " (about " + millions +
                           " M parameters)",
                       static_cast<uint64_t>(parameters) * 4 * sizeof(float),
                       [&] { built.emplace(backend, config, network, renderer, losses); });
  Trainer& trainer = *built;
  // Under mpirun every rank trains on its rows of each batch; rank 0 alone writes the run
  // folder and draws progress (docs/distributed.md).
  const std::unique_ptr<Communicator> comm = make_communicator();
  trainer.set_communicator(*comm);
  TrainingRunOptions run_options;
  run_options.folder = out;
  run_options.resume = resume;
  run_options.from = from;
  run_options.config_source = config_path;
  run_options.time_limit_seconds = time_limit_minutes * 60.0;
  run_options.overwrite = values.count("overwrite") > 0;
  TrainingRun run(trainer, config, *comm, run_options);
  const bool writer = run.writer();
  if (resume && writer) std::cerr << "resumed " << out << " at step " << trainer.steps_done() << "\n";

  g_stop_signal.store(0);
  // SIGHUP (the terminal closed, the session ended) stops like SIGTERM: checkpoint first.
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, on_stop_signal);
  const int64_t first = run.first_step();
  int64_t images = 0;
  double last_draw = -1.0;
  TrainingRun::Events events;
  events.step = [&](const StepRecord& r, double elapsed) {
    images += r.images;
    const bool last = trainer.steps_done() == config.steps;
    if (elapsed - last_draw <= 0.2 && !last) return;
    std::ostringstream label;
    label << "train loss " << r.total;
    const std::string text =
        format_progress(label.str(), trainer.steps_done() - first, config.steps - first, elapsed, "step");
    std::cerr << "\r" << text << " " << static_cast<double>(images) / std::max(elapsed, 1e-9) << " img/s";
    if (time_limit_minutes > 0) {
      const int left = static_cast<int>(std::max(0.0, time_limit_minutes * 60.0 - elapsed));
      char clock[32];
      std::snprintf(clock, sizeof clock, " (time limit in %d:%02d)", left / 60, left % 60);
      std::cerr << clock;
    }
    std::cerr << std::flush;
    last_draw = elapsed;
  };
  events.validation = [](const ValidationRecord& v) {
    std::cerr << "\nstep " << v.step << ": validation normal error " << v.normal_error_mean_deg << " +- "
              << v.normal_error_std_deg << " deg\n";
  };
  events.stop_signal = [] { return g_stop_signal.load(); };
  const RunOutcome outcome = run.run(events);
  if (outcome == RunOutcome::Diverged) std::cerr << "\n" << run.divergence() << " (" << run.checkpoint_path() << ")\n";
  if (writer) std::cerr << "\n";
  int exit_code = 0;
  if (outcome == RunOutcome::Diverged) {
    exit_code = 3;
  } else if (outcome == RunOutcome::Stopped) {
    exit_code = 128 + (run.stop_signal() != 0 ? run.stop_signal() : SIGTERM);
    if (writer)
      std::cerr << "stopped by signal at step " << trainer.steps_done() << "; checkpoint written to "
                << run.checkpoint_path() << " (continue with --resume)\n";
  } else if (writer && outcome == RunOutcome::OutOfTime) {
    std::cerr << "time limit of " << time_limit_minutes << " min reached at step " << trainer.steps_done()
              << " of " << config.steps << "; checkpoint written to " << run.checkpoint_path()
              << " (continue with --resume); weights in " << run.weights_path() << "\n";
  } else if (writer) {
    std::cerr << "trained " << trainer.steps_done() << " steps; weights in " << run.weights_path() << "\n";
  }
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, SIG_DFL);
  return exit_code;
}

const CommandRegistration registration{
    {"train", "train the network from a configuration (paper stages 1 and 2), with resume",
     run_train_command}};

}  // namespace
}  // namespace facetool
