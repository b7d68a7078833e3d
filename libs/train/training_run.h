// TrainingRun: a run folder around a Trainer (checkpoint.safetensors, weights.safetensors,
// log.jsonl, loss.png): starting, resuming, starting from other weights, the validation and
// checkpoint timing, and stopping on request or at a time limit (docs/training.md).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "libs/distributed/communicator.h"
#include "libs/train/trainer.h"
#include "libs/train/training_config.h"
#include "core/util/folder_lock.h"

namespace facetool {

struct TrainingRunOptions {
  std::string folder;              // the run folder
  bool resume = false;             // continue the run in `folder` from its checkpoint
  std::string from;                // weights file or checkpoint to start from (not with resume)
  std::string config_source;       // the configuration's file, named in messages
  double time_limit_seconds = 0;   // stop after this much wall time (0: none)
  bool overwrite = false;          // a fresh run may replace another run's weights and log without a checkpoint
};

enum class RunOutcome {
  Finished,   // every step of the configuration taken; checkpoint and weights written
  Stopped,    // stop_signal() reported a signal; checkpoint written
  OutOfTime,  // the time limit; checkpoint written
  Diverged,   // TrainingDiverged; the loss curve written, the last checkpoint kept
};

class TrainingRun {
 public:
  // Prepares the folder: with options.resume restores its checkpoint (and trims log.jsonl to the
  // restored step), else refuses a folder that holds a run (a checkpoint; or weights or a log,
  // unless options.overwrite), creates it and loads options.from. Rank 0, the only one that
  // writes files, holds the folder's lock (folder_lock.h) for the run's lifetime: a second run
  // into the folder is refused. The trainer must outlive the run.
  TrainingRun(Trainer& trainer, const TrainingConfig& config, Communicator& comm,
              const TrainingRunOptions& options);

  struct Events {
    // After every step, on rank 0, with the wall seconds since run() began.
    std::function<void(const StepRecord&, double elapsed)> step;
    // After each validation that measured pixels, on rank 0.
    std::function<void(const ValidationRecord&)> validation;
    // A stop request (e.g. a signal number; 0: none), polled after every step; the ranks agree.
    std::function<int()> stop_signal;
  };
  // Trains until the configuration's steps, a stop request, the time limit or divergence;
  // validates every validation_every steps and at the end, checkpoints every checkpoint_every.
  RunOutcome run(const Events& events);

  bool writer() const { return writer_; }
  int64_t first_step() const { return first_step_; }
  int stop_signal() const { return stop_signal_; }  // the request that stopped run()
  const std::string& divergence() const { return divergence_; }  // TrainingDiverged's message
  const std::string& checkpoint_path() const { return checkpoint_; }
  const std::string& weights_path() const { return weights_; }
  const std::string& log_path() const { return log_path_; }
  const std::string& curve_path() const { return curve_; }

  // save_all(), then `outcome`; RunOutcome::Diverged when the weights are not finite.
  RunOutcome save_at_end(RunOutcome outcome);
  // Writes the checkpoint, the weights and the loss curve (rank 0); throws TrainingDiverged, writing
  // nothing, when the weights are not finite.
  void save_all();

 private:
  Trainer& trainer_;
  const TrainingConfig& config_;
  Communicator& comm_;
  TrainingRunOptions options_;
  bool writer_ = false;
  int64_t first_step_ = 0;
  int stop_signal_ = 0;
  std::string divergence_;
  std::string checkpoint_, weights_, log_path_, curve_;
  std::vector<std::pair<double, double>> points_;  // (step, total) for the loss curve
  std::unique_ptr<FolderLock> lock_;               // rank 0's
};

// Loads `path` into `network` to start a run from it: a checkpoint's network tensors, or a weights
// file whose width and input size must be the configuration's (`config_source` named in messages).
void load_starting_weights(NetworkPlugin& network, const std::string& path, const TrainingConfig& config,
                           const std::string& config_source);

}  // namespace facetool
