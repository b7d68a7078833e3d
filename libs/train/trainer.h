// Trainer: one training stage's steps (data, network, loss terms, renderer, Adam), validation, checkpoints.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "libs/data/dataset_reader.h"
#include "libs/distributed/communicator.h"
#include "core/plugin/loss_plugin.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/renderer_plugin.h"
#include "libs/train/adam_optimizer.h"
#include "libs/train/checkpoint.h"
#include "libs/train/training_config.h"
#include "core/util/error.h"

namespace facetool {

// A NaN or infinite loss: training stops before the optimiser touches the weights.
class TrainingDiverged : public Error {
 public:
  using Error::Error;
};

struct StepRecord {
  int64_t step = 0;  // 1-based number of the step just taken
  double total = 0;  // weighted sum of every term of every source
  std::vector<std::pair<std::string, double>> terms;  // "source/term" -> unweighted value
  int64_t images = 0;
  double seconds_data = 0, seconds_total = 0;  // waiting for batches / the whole step
  double seconds_allreduce = 0;  // summing gradients over the ranks (0 in one process)
};

struct ValidationRecord {
  int64_t step = 0;
  int64_t pixels = 0;
  double normal_error_mean_deg = 0, normal_error_std_deg = 0;
};

class Trainer {
 public:
  // The network is built here from the configuration (width, input size) and initialised with
  // random weights from the configuration's `seed` unless restore() or load weights follow. Every term named in the configuration
  // must be provided by one of `losses` (checked here, before any step).
  Trainer(Backend& backend, TrainingConfig config, std::shared_ptr<NetworkPlugin> network,
          std::shared_ptr<RendererPlugin> renderer,
          std::vector<std::shared_ptr<LossPlugin>> losses);
  ~Trainer();

  // Continues from a checkpoint: weights, moments, step, data position.
  void restore(const std::string& checkpoint_path);
  void save(const std::string& checkpoint_path) const;

  // One optimiser step over one batch of every source. Throws TrainingDiverged naming the step
  // and term when a loss is not finite (the weights are left as they were).
  StepRecord step();
  // Mean normal angular error over the validation part of the first labelled source.
  ValidationRecord validate();

  // Data-parallel training (docs/distributed.md): every rank reads the global batch of each
  // source (the configuration's `batch`) and trains on its rows (rank_rows); each term is
  // weighted by this rank's share of the term's normaliser (masked pixels, or images for terms
  // of the light alone), gradients are summed over the ranks in buckets and batch norm uses the
  // global batch's statistics, so K ranks take the step one process takes on the whole batch.
  // Call before the first step; `comm` must outlive the trainer.
  void set_communicator(Communicator& comm);

  // About the memory one step takes (bytes), for "out of memory while ..." messages: the
  // parameters with their gradients and Adam moments, and per image of every source's batch
  // about 128 bytes per pixel and width channel (measured on the paper network at width 256,
  // 32x32: 1.0 GB peak at batch 8, 0.88 GB at batch 4). Rough: the network plugin's own layers
  // decide. And what one step trains on, e.g. "batch 8 of 32x32 images at width 256".
  static uint64_t step_memory_estimate(const TrainingConfig& config, int64_t parameters);
  static std::string step_description(const TrainingConfig& config);
  // The parameters of a network of `config`'s width, before it is built: 225 x width^2 for the
  // paper network (3.69 M at width 128).
  static int64_t parameter_estimate(const TrainingConfig& config);
  int64_t parameter_count() const;

  int64_t steps_done() const { return step_; }
  const TrainingConfig& config() const { return config_; }
  NetworkPlugin& network() { return *network_; }

 private:
  struct Source;
  Backend& backend_;
  TrainingConfig config_;
  std::shared_ptr<NetworkPlugin> network_;
  std::shared_ptr<RendererPlugin> renderer_;
  std::vector<std::shared_ptr<LossPlugin>> losses_;
  std::vector<std::unique_ptr<Source>> sources_;
  std::unique_ptr<AdamOptimizer> optimizer_;
  int64_t step_ = 0;
  SingleProcessCommunicator single_;
  Communicator* comm_ = &single_;
  bool synced_batch_norm_ = false;  // this trainer installed the batch-norm statistics sum
  void allreduce_gradients();
};

}  // namespace facetool
