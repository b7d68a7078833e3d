// Training checkpoints: weights, batch-norm state, Adam moments, step and data position in one file.
#pragma once

#include <cstdint>
#include <string>

#include "libs/model/safetensors.h"
#include "core/plugin/network_plugin.h"
#include "libs/train/adam_optimizer.h"

namespace facetool {

// Everything besides tensors that a resumed run needs to continue exactly. The data order is
// stateless given the seed (epoch e is shuffled with derive_seed(seed, e)), so the position is
// the number of batches each source has served, which is the step count.
struct CheckpointState {
  int64_t step = 0;      // optimiser steps taken
  uint64_t seed = 0;     // the configuration's seed (data order)
  std::string config_name;
  std::string architecture;  // network plugin name
  NetworkConfig network;
};

// One safetensors file (docs/training.md): "network/<name>" for every parameter and buffer,
// "adam/<name>.adam_m" and ".adam_v" for the moments, metadata format = "facetool-checkpoint",
// format_version = "1", step, seed, config, architecture, width, input_size. Written atomically
// (temporary file, then rename), so a write that is killed leaves the previous checkpoint.
void save_checkpoint(const std::string& path, const NetworkPlugin& network,
                     const AdamOptimizer& optimizer, const CheckpointState& state);

// Reads the state only (to build a matching network first).
CheckpointState read_checkpoint_state(const std::string& path);
// Restores weights, buffers and moments into a network built with the checkpoint's
// configuration and an optimiser over its parameters; fails naming the tensor that is missing
// or of another shape. Returns the state.
CheckpointState load_checkpoint(const std::string& path, NetworkPlugin& network,
                                AdamOptimizer& optimizer);

// Whether `file` is a checkpoint (metadata format "facetool-checkpoint") rather than a weights file.
bool is_checkpoint(const SafeTensors& file);
// Only the network's weights and buffers of checkpoint `file` (read from `path`), no moments and no
// step: to start another run from it. Fails naming a tensor that is missing or of another shape.
void load_checkpoint_network(const SafeTensors& file, const std::string& path, NetworkPlugin& network);

}  // namespace facetool
