// TrainingConfig: one training stage read from a JSON file (docs/training.md), checked before step 1.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/plugin/loss_plugin.h"
#include "libs/image/crop_framing.h"

namespace facetool {

struct WeightedTerm {
  std::string name;  // a term of a loaded loss plugin, e.g. "recon_albedo"
  double weight = 0;
};

// One part of each step's batch: `batch` samples from `directory`, scored by `terms`.
struct DataSource {
  std::string name;       // e.g. "synthetic", "real"; used in the log ("synthetic/recon_albedo")
  std::string kind;       // "synthetic" (all labels), "pseudo_labelled" (all, predicted), "real"
                          // (image and mask only)
  std::string directory;  // relative paths are taken from the configuration file's folder
  int batch = 20;
  // Fraction of this source's input photos given to the network in grey (libs/train/grey_inputs.h),
  // so that it does not lean on colour that grey photos lack; the loss targets stay in colour.
  double grey_fraction = 0;
  // Fraction of this source's labelled photos relit by a random one-sided light through their
  // labels (libs/train/relit_inputs.h): input and reconstruction target alike, the light label
  // replaced; before the grey rows are picked. Needs labels (not kind "real").
  double relight_fraction = 0;
  // How the relit photos' new light shades the network's input: "sh" (its 9 SH coefficients,
  // input and target alike) or "hard" (the exact distant light with its cast shadows for the
  // input, the SH rendering kept as the target; libs/train/relit_inputs.h).
  std::string relight_light = "sh";
  // Fraction of this source's samples seen in a left-right mirror, labels and all
  // (libs/train/mirrored_inputs.h); before the relit and grey rows are picked.
  double mirror_fraction = 0;
  std::vector<WeightedTerm> terms;
  uint32_t provides() const;  // LossNeeds bits the kind supplies
};

struct TrainingConfig {
  std::string path;  // the file it came from (for messages)
  std::string name;
  std::string network = "paper_network";
  int width = 128, input_size = 128;
  // network.framing: how the samples' crops are framed ("v1", "v2" or framing_text's form);
  // written into the weights (libs/model/network_weights.h) so infer frames photos the same way.
  CropFraming framing;
  // network.input_prior: NetworkConfig::input_prior ("" or "fit_normal"); the samples of every
  // source then carry the prior channels (libs/data/training_sample.h).
  std::string input_prior = "";
  std::string renderer = "sh_renderer";
  double learning_rate = 1e-4, beta1 = 0.9, beta2 = 0.999, epsilon = 1e-8;
  int64_t steps = 1000;
  int64_t checkpoint_every = 1000;
  int64_t validation_every = 1000;
  int validation_holdout_every = 20;  // sample index % k == 0 is held out (0: no validation)
  int validation_batches = 4;
  uint64_t seed = 0;
  std::vector<DataSource> sources;
};

// Reads and checks the file: JSON syntax, known keys only, types and ranges. Throws
// facetool::Error naming the file and the key at fault.
TrainingConfig read_training_config(const std::string& path);
TrainingConfig parse_training_config(const std::string& json_text, const std::string& path);

// Checks every source's terms against the loaded terms: unknown names (listing the known ones)
// and terms needing inputs the source's kind lacks. Throws facetool::Error.
void check_terms(const TrainingConfig& config, const std::vector<LossTermInfo>& available);

}  // namespace facetool
