// `facetool train`: runs one training stage from a configuration file into a run folder.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "core/backend/registry.h"
#include "core/distributed/communicator.h"
#include "core/util/atomic_file.h"
#include "core/model/network_weights.h"
#include "core/train/loss_curve.h"
#include "core/train/trainer.h"
#include "core/util/file_checks.h"
#include "core/util/folder_lock.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

// A run's log is one line per step: 1 GiB is millions of steps.
constexpr uint64_t kMaxLogFileBytes = uint64_t{1} << 30;

std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int signal) { g_stop_signal.store(signal); }

// Reads RUN/log.jsonl, keeping the lines of steps <= `last_step` (a resumed run rewrites the
// rest), and returns the (step, total) points of the training lines.
std::vector<std::pair<double, double>> trim_log(const std::string& path, int64_t last_step) {
  std::vector<std::pair<double, double>> points;
  std::error_code missing;
  if (!std::filesystem::exists(path, missing)) return points;
  std::istringstream in(read_regular_input_file(path, kMaxLogFileBytes, "training log"));
  std::string line, kept;
  while (std::getline(in, line)) {
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("step") || !j["step"].is_number() ||
        j["step"].get<double>() > static_cast<double>(last_step))
      continue;
    kept += line + "\n";
    if (j.contains("total") && j["total"].is_number())
      points.emplace_back(j["step"].get<double>(), j["total"].get<double>());
  }
  write_file_atomically(path, kept.data(), kept.size());
  return points;
}

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
  Trainer trainer(backend, config, network, renderer, losses);
  // Under mpirun every rank trains on its rows of each batch; rank 0 alone writes the run
  // folder and draws progress (docs/distributed.md).
  const std::unique_ptr<Communicator> comm = make_communicator();
  trainer.set_communicator(*comm);
  const bool writer = comm->rank() == 0;

  namespace fs = std::filesystem;
  const std::string checkpoint = (fs::path(out) / "checkpoint.safetensors").string();
  const std::string log_path = (fs::path(out) / "log.jsonl").string();
  const std::string weights = (fs::path(out) / "weights.safetensors").string();
  const std::string curve = (fs::path(out) / "loss.png").string();
  std::vector<std::pair<double, double>> points;
  // One run per folder: a second train (or any facetool run) into RUN is refused while this one
  // writes there. Only rank 0 writes, so only rank 0 locks.
  std::unique_ptr<FolderLock> lock;
  if (writer) {
    if (!resume) {
      std::error_code ec;
      fs::create_directories(out, ec);
      check(!ec, "cannot create --out '", out, "': ", ec.message());
    }
    check_input_folder(out, "--out");
    lock = std::make_unique<FolderLock>(out, "--out");
  }
  if (resume) {
    check(fs::exists(checkpoint), "--resume: '", checkpoint, "' does not exist; start the run ",
          "without --resume");
    trainer.restore(checkpoint);
    if (writer) points = trim_log(log_path, trainer.steps_done());
    if (writer) std::cerr << "resumed " << out << " at step " << trainer.steps_done() << "\n";
  } else {
    check(!fs::exists(checkpoint), "'", out, "' already holds a run (", checkpoint,
          "); pass --resume to continue it or choose another --out");
    // A finished or diverged run without a checkpoint still holds results worth keeping.
    // (An empty log is a run that failed before its first step: nothing to keep.)
    for (const std::string& earlier : {weights, log_path})
      check(!fs::exists(earlier) || fs::file_size(earlier) == 0 || values.count("overwrite"),
            "--out '", out, "' holds another run's results ('", earlier, "') but no checkpoint ",
            "to resume; choose another --out, or pass --overwrite to replace them");
    if (!from.empty()) {
      const SafeTensors file = SafeTensors::read_file(from);
      if (file.metadata().count("format") && file.metadata().at("format") == "facetool-checkpoint") {
        for (const auto& [name, p] : network->parameters()) p.value().copy_from_host(file.floats("network/" + name));
        for (const auto& [name, t] : network->buffers()) t.copy_from_host(file.floats("network/" + name));
      } else {
        const WeightsHeader header = read_weights_header(file, from);
        check(header.config.width == config.width && header.config.input_size == config.input_size,
              "--from '", from, "' holds width ", header.config.width, " input ",
              header.config.input_size, " but '", config_path, "' asks for width ", config.width,
              " input ", config.input_size);
        load_network_weights(*network, file, from);
      }
    }
  }
  // The log is opened at the first line, so that a run failing before its first step (a bad
  // sample, an unknown source) leaves no empty log behind; a fresh run replaces an earlier one.
  std::ofstream log;
  auto open_log = [&] {
    if (!writer || log.is_open()) return;
    log.open(log_path, resume ? std::ios::app : std::ios::trunc);
    check(log.good(), "cannot write '", log_path, "'");
  };

  g_stop_signal.store(0);
  // SIGHUP (the terminal closed, the session ended) stops like SIGTERM: checkpoint first.
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, on_stop_signal);
  auto save_all = [&] {
    if (!writer) return;
    trainer.save(checkpoint);  // throws TrainingDiverged rather than write non-finite weights
    save_network_weights(trainer.network(), config.network, weights);
    write_loss_curve(curve, points);
  };

  const int64_t first = trainer.steps_done();
  const auto start = std::chrono::steady_clock::now();
  int64_t images = 0;
  double last_draw = -1.0;
  int exit_code = 0;
  bool out_of_time = false;
  auto report_divergence = [&](const TrainingDiverged& e) {
    std::cerr << "\n" << e.what() << " (" << checkpoint << ")\n";
    exit_code = 3;
  };
  while (trainer.steps_done() < config.steps) {
    StepRecord r;
    try {
      r = trainer.step();
    } catch (const TrainingDiverged& e) {
      report_divergence(e);
      break;
    }
    images += r.images;
    open_log();
    nlohmann::json line = {{"step", r.step}, {"total", r.total}, {"images", r.images},
                           {"seconds", r.seconds_total}, {"seconds_data", r.seconds_data}};
    for (const auto& [name, v] : r.terms) line["terms"][name] = v;
    log << line.dump() << "\n" << std::flush;
    points.emplace_back(static_cast<double>(r.step), r.total);
    const bool last = trainer.steps_done() == config.steps;
    if (writer && (r.step % config.validation_every == 0 || last)) {
      const ValidationRecord v = trainer.validate();
      if (v.pixels > 0) {
        log << nlohmann::json{{"step", v.step},
                              {"validation", {{"normal_error_mean_deg", v.normal_error_mean_deg},
                                              {"normal_error_std_deg", v.normal_error_std_deg},
                                              {"pixels", v.pixels}}}}
                   .dump()
            << "\n"
            << std::flush;
        std::cerr << "\nstep " << v.step << ": validation normal error "
                  << v.normal_error_mean_deg << " +- " << v.normal_error_std_deg << " deg\n";
      }
    }
    if (r.step % config.checkpoint_every == 0 && !last) {
      try {
        save_all();
      } catch (const TrainingDiverged& e) {
        report_divergence(e);
        break;
      }
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (writer && (elapsed - last_draw > 0.2 || last)) {
      std::ostringstream label;
      label << "train loss " << r.total;
      const std::string text =
          format_progress(label.str(), trainer.steps_done() - first, config.steps - first, elapsed, "step");
      std::cerr << "\r" << text << " " << static_cast<double>(images) / std::max(elapsed, 1e-9)
                << " img/s";
      if (time_limit_minutes > 0) {
        const int left = static_cast<int>(std::max(0.0, time_limit_minutes * 60.0 - elapsed));
        char clock[32];
        std::snprintf(clock, sizeof clock, " (time limit in %d:%02d)", left / 60, left % 60);
        std::cerr << clock;
      }
      std::cerr << std::flush;
      last_draw = elapsed;
    }
    // A signal may reach the ranks at different steps: all stop at the step any rank saw it.
    // The time limit goes by rank 0's clock, so that every rank stops after the same step. One
    // sum carries both.
    const bool late = writer && time_limit_minutes > 0 && elapsed >= time_limit_minutes * 60.0;
    std::vector<double> stop{static_cast<double>(g_stop_signal.load()), late ? 1.0 : 0.0};
    comm->allreduce_sum(stop);
    if (stop[0] != 0) {
      exit_code = 128 + (g_stop_signal.load() != 0 ? g_stop_signal.load() : SIGTERM);
      break;
    }
    if (stop[1] != 0 && trainer.steps_done() < config.steps) {
      out_of_time = true;
      break;
    }
  }
  if (writer) std::cerr << "\n";
  if (exit_code != 3) {
    try {
      save_all();
    } catch (const TrainingDiverged& e) {
      report_divergence(e);
    }
  }
  if (exit_code == 3) {
    if (writer) write_loss_curve(curve, points);
    for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, SIG_DFL);
    return exit_code;
  }
  if (writer && exit_code != 0)
    std::cerr << "stopped by signal at step " << trainer.steps_done() << "; checkpoint written to "
              << checkpoint << " (continue with --resume)\n";
  else if (writer && out_of_time)
    std::cerr << "time limit of " << time_limit_minutes << " min reached at step "
              << trainer.steps_done() << " of " << config.steps << "; checkpoint written to "
              << checkpoint << " (continue with --resume); weights in " << weights << "\n";
  else if (writer)
    std::cerr << "trained " << trainer.steps_done() << " steps; weights in " << weights << "\n";
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, SIG_DFL);
  return exit_code;
}

const CommandRegistration registration{
    {"train", "train the network from a configuration (paper stages 1 and 2), with resume",
     run_train_command}};

}  // namespace
}  // namespace facetool
