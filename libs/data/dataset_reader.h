// DatasetReader: shuffled batches of samples (facetool synth EXR files, or real ones from
// prepare-real / pseudo-label: libs/data/training_sample.h) as tensors, decoded on a background
// thread while the caller trains.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/tensor/tensor.h"

namespace facetool {

class Backend;

// One batch, NCHW: image [N,3,H,W], albedo [N,3,H,W], normal [N,3,H,W], mask [N,1,H,W] (the
// head mask eroded by one pixel, the region the losses use), visibility [N,9,H,W], light
// [N,27] (channel-major R0..R8 G0..G8 B0..B8); prior [N,P,H,W], the network's input prior when
// the reader was asked for one (undefined otherwise).
struct SyntheticBatch {
  Tensor image, albedo, normal, mask, visibility, light, prior;
  // When defined, what the network reads in place of `image`, which stays the losses' target
  // (training's hard-relit rows, libs/train/relit_inputs.h); never set by the reader.
  Tensor input_image;
  std::vector<std::string> files;  // the samples, in batch order
  int64_t epoch = 0;               // the pass over the data the batch belongs to (0-based)

  // What the network reads: the image (input_image when defined), followed by the prior's
  // channels when there is one.
  Tensor network_input() const;
};

struct DatasetReaderOptions {
  std::string directory;  // holds sample_*.exr (every one is used, whatever the shard)
  int batch_size = 20;
  uint64_t seed = 0;      // shuffle order: the same seed gives the same batches
  bool shuffle = true;
  int prefetch = 2;       // batches decoded ahead
  // Held-out split by sample index (the number in sample_XXXXXXXX.exr): with holdout_every = k
  // > 0, samples whose index % k == 0 form the validation part. `part` picks which part this
  // reader serves; kAll ignores the split.
  enum class Part { kAll, kTraining, kValidation };
  int holdout_every = 0;
  Part part = Part::kAll;
  int64_t start_batch = 0;  // the first batch served (resuming: batches already consumed)
  // Real samples (facetool-real-1) must carry pseudo labels; without, their labels are zeros.
  bool require_labels = true;
  // NetworkConfig::input_prior: every sample must carry it (read_training_sample).
  std::string input_prior = "";
};

class DatasetReader {
 public:
  // Lists the samples (throws facetool::Error when the folder has none or does not exist) and
  // starts the background thread.
  DatasetReader(Backend& backend, DatasetReaderOptions options);
  ~DatasetReader();
  DatasetReader(const DatasetReader&) = delete;
  DatasetReader& operator=(const DatasetReader&) = delete;

  size_t sample_count() const { return files_.size(); }
  const std::vector<std::string>& files() const { return files_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // The first sample's framing text (read_training_sample_framing: "v1" when not recorded).
  const std::string& framing() const { return framing_; }

  // The next batch; blocks until it is decoded. Batches run through a fresh permutation every
  // epoch; the last batch of an epoch is dropped when it would be short. A file that fails to
  // load throws facetool::Error here.
  SyntheticBatch next();

 private:
  struct HostBatch;
  void produce();
  HostBatch load_batch(int64_t batch_number);

  Backend& backend_;
  DatasetReaderOptions options_;
  std::vector<std::string> files_;
  int width_ = 0, height_ = 0;
  std::string framing_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<HostBatch> ready_;
  bool stopping_ = false;
  std::thread worker_;
};

}  // namespace facetool
