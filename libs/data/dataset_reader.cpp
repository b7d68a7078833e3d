// DatasetReader: file listing, per-epoch permutations, EXR decoding on a worker thread.
#include "libs/data/dataset_reader.h"

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <filesystem>

#include "libs/data/training_sample.h"
#include "libs/synth/gbuffer.h"
#include "libs/synth/random.h"
#include "libs/synth/synth_sample.h"
#include "core/ops/ops.h"
#include "core/plugin/network_plugin.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"

namespace facetool {
namespace fs = std::filesystem;

struct DatasetReader::HostBatch {
  std::vector<float> image, albedo, normal, mask, visibility, light, prior;
  std::vector<std::string> files;
  int64_t epoch = 0;
  std::exception_ptr error;
};

DatasetReader::DatasetReader(Backend& backend, DatasetReaderOptions options)
    : backend_(backend), options_(std::move(options)) {
  check(options_.batch_size > 0, "dataset reader: batch size must be positive, got ",
        options_.batch_size);
  std::error_code error;
  check(fs::exists(options_.directory, error) || error, "dataset folder '", options_.directory,
        "' does not exist; make samples with `facetool synth --out DIR`");
  // A sample that cannot be read (a link to nothing, a link loop, a pipe) is an error: training
  // on fewer samples than the folder shows would be silently wrong.
  std::vector<std::string> problems;
  files_ = list_folder_files(
      options_.directory, "dataset folder",
      [](const std::string& name) {
        return name.rfind("sample_", 0) == 0 && fs::path(name).extension() == ".exr";
      },
      problems);
  check(problems.empty(), "dataset sample ", problems.empty() ? "" : problems[0],
        problems.size() > 1 ? " (and " + std::to_string(problems.size() - 1) + " more)" : "",
        "; fix or remove it");
  check(!files_.empty(), "dataset folder '", options_.directory,
        "' holds no sample_*.exr files; make them with `facetool synth --out DIR`");
  check(options_.start_batch >= 0, "dataset reader: start batch must be >= 0");
  if (options_.holdout_every > 0 && options_.part != DatasetReaderOptions::Part::kAll) {
    const bool want_validation = options_.part == DatasetReaderOptions::Part::kValidation;
    std::vector<std::string> kept;
    for (const std::string& file : files_) {
      const std::string stem = fs::path(file).stem().string().substr(7);  // after "sample_"
      char* end = nullptr;
      const long long index = std::strtoll(stem.c_str(), &end, 10);
      check(!stem.empty() && end && *end == '\0', "dataset file '", file,
            "' is not named sample_<number>.exr, so it cannot be assigned to the training or "
            "validation part");
      if ((index % options_.holdout_every == 0) == want_validation) kept.push_back(file);
    }
    files_ = std::move(kept);
    check(!files_.empty(), "dataset folder '", options_.directory, "' has no samples in its ",
          want_validation ? "validation" : "training", " part (every ", options_.holdout_every,
          "th sample index is held out); add samples or change the split");
  }
  // Too few for one batch: say which part of the split ran short, and what to change.
  const bool split = options_.holdout_every > 0 && options_.part != DatasetReaderOptions::Part::kAll;
  std::string part;
  if (split && options_.part == DatasetReaderOptions::Part::kValidation)
    part = " in its validation part (the sample indices divisible by " +
           std::to_string(options_.holdout_every) + ")";
  else if (split)
    part = " in its training part";
  check(files_.size() >= static_cast<size_t>(options_.batch_size), "dataset folder '",
        options_.directory, "' holds ", files_.size(), " samples", part,
        ", fewer than one batch of ", options_.batch_size,
        split ? "; add samples, or change the batch or the split (validation.holdout_every)"
              : "; add samples or use a smaller batch");
  read_training_sample_size(files_[0], width_, height_);
  framing_ = read_training_sample_framing(files_[0]);
  worker_ = std::thread([this] { produce(); });
}

DatasetReader::~DatasetReader() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

DatasetReader::HostBatch DatasetReader::load_batch(int64_t batch_number) {
  const int64_t per_epoch = static_cast<int64_t>(files_.size()) / options_.batch_size;
  HostBatch batch;
  batch.epoch = batch_number / per_epoch;
  std::vector<size_t> order(files_.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  if (options_.shuffle) {  // Fisher-Yates with the generator's portable RNG
    Random random(derive_seed(options_.seed, static_cast<uint64_t>(batch.epoch)));
    for (size_t k = order.size(); k > 1; --k) std::swap(order[k - 1], order[random.index(k)]);
  }
  const int64_t first = (batch_number % per_epoch) * options_.batch_size;
  for (int b = 0; b < options_.batch_size; ++b) {
    const std::string& file = files_[order[first + b]];
    const TrainingSample s = read_training_sample(file, options_.require_labels, options_.input_prior);
    check(s.width == width_ && s.height == height_, "sample '", file, "' is ", s.width, "x",
          s.height, " but the dataset's first sample is ", width_, "x", height_);
    batch.files.push_back(file);
    batch.image.insert(batch.image.end(), s.image.begin(), s.image.end());
    batch.albedo.insert(batch.albedo.end(), s.albedo.begin(), s.albedo.end());
    batch.normal.insert(batch.normal.end(), s.normal.begin(), s.normal.end());
    const std::vector<float> eroded = erode_mask(s.mask, s.width, s.height);
    batch.mask.insert(batch.mask.end(), eroded.begin(), eroded.end());
    batch.visibility.insert(batch.visibility.end(), s.visibility.begin(), s.visibility.end());
    batch.light.insert(batch.light.end(), s.light.begin(), s.light.end());
    batch.prior.insert(batch.prior.end(), s.prior.begin(), s.prior.end());
  }
  return batch;
}

void DatasetReader::produce() {
  for (int64_t batch_number = options_.start_batch;; ++batch_number) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] {
        return stopping_ || ready_.size() < static_cast<size_t>(std::max(options_.prefetch, 1));
      });
      if (stopping_) return;
    }
    HostBatch batch;
    try {
      batch = load_batch(batch_number);
    } catch (...) {
      batch.error = std::current_exception();
    }
    const bool failed = batch.error != nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(batch));
    }
    changed_.notify_all();
    if (failed) return;  // the consumer rethrows; nothing sensible follows
  }
}

SyntheticBatch DatasetReader::next() {
  HostBatch host;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return !ready_.empty(); });
    host = std::move(ready_.front());
    if (!host.error) ready_.pop_front();
  }
  changed_.notify_all();
  if (host.error) std::rethrow_exception(host.error);
  const int64_t n = options_.batch_size, h = height_, w = width_;
  SyntheticBatch batch;
  batch.image = Tensor::from_host(backend_, Shape{n, 3, h, w}, host.image);
  batch.albedo = Tensor::from_host(backend_, Shape{n, 3, h, w}, host.albedo);
  batch.normal = Tensor::from_host(backend_, Shape{n, 3, h, w}, host.normal);
  batch.mask = Tensor::from_host(backend_, Shape{n, 1, h, w}, host.mask);
  batch.visibility = Tensor::from_host(backend_, Shape{n, 9, h, w}, host.visibility);
  batch.light = Tensor::from_host(backend_, Shape{n, 27}, host.light);
  if (!options_.input_prior.empty())
    batch.prior = Tensor::from_host(backend_, Shape{n, input_prior_channels(options_.input_prior), h, w}, host.prior);
  batch.files = std::move(host.files);
  batch.epoch = host.epoch;
  return batch;
}

Tensor SyntheticBatch::network_input() const {
  const Tensor& seen = input_image.defined() ? input_image : image;
  return prior.defined() ? ops::concat_channels({seen, prior}) : seen;
}

}  // namespace facetool
