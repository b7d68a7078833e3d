// TrainingRun: the run folder, resume, starting weights, validation and checkpoint timing, stops.
#include "libs/train/training_run.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "libs/model/network_weights.h"
#include "libs/model/safetensors.h"
#include "libs/train/checkpoint.h"
#include "libs/train/loss_curve.h"
#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/memory_budget.h"

namespace fs = std::filesystem;

namespace facetool {
namespace {

// A run's log is one line per step: 1 GiB is millions of steps.
constexpr uint64_t kMaxLogFileBytes = uint64_t{1} << 30;

// Reads RUN/log.jsonl, keeping the lines of steps <= `last_step` (a resumed run rewrites the
// rest), and returns the (step, total) points of the training lines.
std::vector<std::pair<double, double>> trim_log(const std::string& path, int64_t last_step) {
  std::vector<std::pair<double, double>> points;
  std::error_code missing;
  if (!fs::exists(path, missing)) return points;
  std::istringstream in(read_regular_input_file(path, kMaxLogFileBytes, "training log"));
  std::string line, kept;
  while (std::getline(in, line)) {
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("step") || !j["step"].is_number() ||
        j["step"].get<double>() > static_cast<double>(last_step))
      continue;
    kept += line + "\n";
    if (j.contains("total") && j["total"].is_number()) points.emplace_back(j["step"].get<double>(), j["total"].get<double>());
  }
  write_file_atomically(path, kept.data(), kept.size());
  return points;
}

}  // namespace

void load_starting_weights(NetworkPlugin& network, const std::string& path, const TrainingConfig& config,
                           const std::string& config_source) {
  const SafeTensors file = SafeTensors::read_file(path);
  if (is_checkpoint(file)) {
    load_checkpoint_network(file, path, network);
    return;
  }
  const WeightsHeader header = read_weights_header(file, path);
  check(header.config.width == config.width && header.config.input_size == config.input_size,
        "--from '", path, "' holds width ", header.config.width, " input ", header.config.input_size,
        " but '", config_source, "' asks for width ", config.width, " input ", config.input_size);
  load_network_weights(network, file, path);
}

TrainingRun::TrainingRun(Trainer& trainer, const TrainingConfig& config, Communicator& comm,
                         const TrainingRunOptions& options)
    : trainer_(trainer), config_(config), comm_(comm), options_(options) {
  writer_ = comm.rank() == 0;
  const fs::path out = options.folder;
  checkpoint_ = (out / "checkpoint.safetensors").string();
  log_path_ = (out / "log.jsonl").string();
  weights_ = (out / "weights.safetensors").string();
  curve_ = (out / "loss.png").string();
  check(!(options.resume && !options.from.empty()), "--resume and --from exclude each other");
  if (writer_) {
    if (!options.resume) {
      std::error_code ec;
      fs::create_directories(out, ec);
      check(!ec, "cannot create --out '", options.folder, "': ", ec.message());
    }
    check_input_folder(options.folder, "--out");
    lock_ = std::make_unique<FolderLock>(options.folder, "--out");
  }
  if (options.resume) {
    check(fs::exists(checkpoint_), "--resume: '", checkpoint_, "' does not exist; start the run ",
          "without --resume");
    trainer_.restore(checkpoint_);
    if (writer_) points_ = trim_log(log_path_, trainer_.steps_done());
  } else {
    check(!fs::exists(checkpoint_), "'", options.folder, "' already holds a run (", checkpoint_,
          "); pass --resume to continue it or choose another --out");
    // A finished or diverged run without a checkpoint still holds results worth keeping.
    // (An empty log is a run that failed before its first step: nothing to keep.)
    for (const std::string& earlier : {weights_, log_path_}) {
      std::error_code ec;
      check(!fs::exists(earlier, ec) || fs::file_size(earlier, ec) == 0 || options.overwrite, "--out '",
            options.folder, "' holds another run's results ('", earlier, "') but no checkpoint to resume; ",
            "choose another --out, or pass --overwrite to replace them");
    }
    if (!options.from.empty()) load_starting_weights(trainer_.network(), options.from, config, options.config_source);
  }
  first_step_ = trainer_.steps_done();
}

void TrainingRun::save_all() {
  if (!writer_) return;
  // The checkpoint holds the weights and both Adam moments, serialised in memory first.
  naming_out_of_memory("writing the checkpoint of step " + std::to_string(trainer_.steps_done()),
                       static_cast<uint64_t>(trainer_.parameter_count()) * 6 * sizeof(float),
                       [&] {
                         trainer_.save(checkpoint_);
                         save_network_weights(trainer_.network(), config_.network, weights_, config_.framing);
                         write_loss_curve(curve_, points_);
                       });
}

RunOutcome TrainingRun::save_at_end(RunOutcome outcome) {
  try {
    save_all();
  } catch (const TrainingDiverged& e) {
    divergence_ = e.what();
    if (writer_) write_loss_curve(curve_, points_);
    return RunOutcome::Diverged;
  }
  return outcome;
}

RunOutcome TrainingRun::run(const Events& events) {
  // The log is opened at the first line, so that a run failing before its first step (a bad
  // sample, an unknown source) leaves no empty log behind; a fresh run replaces an earlier one.
  std::ofstream log;
  auto open_log = [&] {
    if (!writer_ || log.is_open()) return;
    log.open(log_path_, options_.resume ? std::ios::app : std::ios::trunc);
    check(log.good(), "cannot write '", log_path_, "'");
  };
  auto diverged = [&](const TrainingDiverged& e) {
    divergence_ = e.what();
    if (writer_) write_loss_curve(curve_, points_);
    return RunOutcome::Diverged;
  };
  const auto start = std::chrono::steady_clock::now();
  stop_signal_ = 0;
  while (trainer_.steps_done() < config_.steps) {
    StepRecord r;
    const uint64_t step_bytes =
        Trainer::step_memory_estimate(config_, trainer_.parameter_count());
    try {
      r = naming_out_of_memory("running training step " +
                                   std::to_string(trainer_.steps_done() + 1) + " (" +
                                   Trainer::step_description(config_) + ")",
                               step_bytes, [&] { return trainer_.step(); });
    } catch (const TrainingDiverged& e) {
      return diverged(e);
    }
    open_log();
    nlohmann::json line = {{"step", r.step}, {"total", r.total}, {"images", r.images},
                           {"seconds", r.seconds_total}, {"seconds_data", r.seconds_data}};
    for (const auto& [name, v] : r.terms) line["terms"][name] = v;
    log << line.dump() << "\n" << std::flush;
    points_.emplace_back(static_cast<double>(r.step), r.total);
    const bool last = trainer_.steps_done() == config_.steps;
    if (writer_ && (r.step % config_.validation_every == 0 || last)) {
      const ValidationRecord v = naming_out_of_memory(
          "validating after step " + std::to_string(r.step) + " (" +
              Trainer::step_description(config_) + ")",
          step_bytes, [&] { return trainer_.validate(); });
      if (v.pixels > 0) {
        log << nlohmann::json{{"step", v.step},
                              {"validation", {{"normal_error_mean_deg", v.normal_error_mean_deg},
                                              {"normal_error_std_deg", v.normal_error_std_deg},
                                              {"pixels", v.pixels}}}}
                   .dump()
            << "\n"
            << std::flush;
        if (events.validation) events.validation(v);
      }
    }
    if (r.step % config_.checkpoint_every == 0 && !last) {
      try {
        save_all();  // never a checkpoint of non-finite weights
      } catch (const TrainingDiverged& e) {
        return diverged(e);
      }
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (writer_ && events.step) events.step(r, elapsed);
    // A signal may reach the ranks at different steps: all stop at the step any rank saw it.
    // The time limit goes by rank 0's clock, so that every rank stops after the same step. One
    // sum carries both.
    const int signal = events.stop_signal ? events.stop_signal() : 0;
    const bool late = writer_ && options_.time_limit_seconds > 0 && elapsed >= options_.time_limit_seconds;
    std::vector<double> stop{static_cast<double>(signal), late ? 1.0 : 0.0};
    comm_.allreduce_sum(stop);
    if (stop[0] != 0) {
      stop_signal_ = signal;
      return save_at_end(RunOutcome::Stopped);
    }
    if (stop[1] != 0 && trainer_.steps_done() < config_.steps) return save_at_end(RunOutcome::OutOfTime);
  }
  return save_at_end(RunOutcome::Finished);
}

}  // namespace facetool
