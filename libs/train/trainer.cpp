// Trainer: the step loop body, NaN/Inf detection, validation by normal angular error.
#include "libs/train/trainer.h"

#include <chrono>
#include <cmath>

#include "core/autograd/functions.h"
#include "core/autograd/synced_batch_norm.h"
#include "libs/train/grey_inputs.h"
#include "libs/train/mirrored_inputs.h"
#include "libs/train/relit_inputs.h"
#include "core/util/math_constants.h"

namespace facetool {

struct Trainer::Source {
  const DataSource* config = nullptr;
  std::vector<std::pair<const WeightedTerm*, LossPlugin*>> terms;
  std::unique_ptr<DatasetReader> reader;  // created at the first step (after restore)
};

namespace {

LossTargets targets_of(const SyntheticBatch& b, const DataSource& source) {
  LossTargets t;
  t.image = b.image;
  t.mask = b.mask;
  if (source.provides() & kNeedsAlbedo) {
    t.albedo = b.albedo;
    t.normal = b.normal;
    t.visibility = b.visibility;
    t.light = b.light;
  }
  return t;
}

DatasetReaderOptions reader_options(const TrainingConfig& c, const DataSource& s, bool validation) {
  DatasetReaderOptions o;
  o.directory = s.directory;
  o.batch_size = s.batch;
  o.seed = c.seed;
  o.shuffle = !validation;
  o.require_labels = s.kind != "real";
  o.input_prior = c.input_prior;
  o.holdout_every = c.validation_holdout_every;
  o.part = c.validation_holdout_every == 0 ? DatasetReaderOptions::Part::kAll
           : validation                    ? DatasetReaderOptions::Part::kValidation
                                           : DatasetReaderOptions::Part::kTraining;
  return o;
}

// Rows [begin, end) of a tensor whose first dimension is the batch.
Tensor rows_of(const Tensor& t, int64_t begin, int64_t end) {
  if (!t.defined()) return t;
  const Shape& s = t.shape();
  const int64_t per_row = s.numel() / s[0];
  const std::vector<float> all = t.to_host();
  std::vector<float> part(all.begin() + begin * per_row, all.begin() + end * per_row);
  const int64_t n = end - begin;
  Shape sliced = s.rank() == 1   ? Shape{n}
                 : s.rank() == 2 ? Shape{n, s[1]}
                 : s.rank() == 3 ? Shape{n, s[1], s[2]}
                                 : Shape{n, s[1], s[2], s[3]};
  return Tensor::from_host(t.backend(), sliced, part);
}

SyntheticBatch rank_slice(const SyntheticBatch& b, int rank, int size) {
  const auto [begin, end] = rank_rows(b.image.shape().n(), rank, size);
  SyntheticBatch out;
  out.image = rows_of(b.image, begin, end);
  out.albedo = rows_of(b.albedo, begin, end);
  out.normal = rows_of(b.normal, begin, end);
  out.mask = rows_of(b.mask, begin, end);
  out.visibility = rows_of(b.visibility, begin, end);
  out.light = rows_of(b.light, begin, end);
  out.prior = rows_of(b.prior, begin, end);
  out.files.assign(b.files.begin() + begin, b.files.begin() + end);
  out.epoch = b.epoch;
  return out;
}

// A term of the light alone is a mean over images; every other term is a masked mean.
bool plugin_term_is_per_image(const LossPlugin& plugin, const std::string& name) {
  for (const LossTermInfo& info : plugin.terms())
    if (info.name == name) return info.needs == kNeedsLight;
  return false;
}

double mask_total(const Tensor& mask) {
  double total = 0.0;
  for (float v : mask.to_host()) total += v;
  return total;
}

// Gradients travel in buckets of this many floats (4 MiB): few calls, bounded host memory.
constexpr int64_t kBucketFloats = int64_t{1} << 20;

}  // namespace

uint64_t Trainer::step_memory_estimate(const TrainingConfig& config, int64_t parameters) {
  uint64_t images = 0;
  for (const DataSource& s : config.sources) images += static_cast<uint64_t>(s.batch);
  const uint64_t pixels = static_cast<uint64_t>(config.input_size) * config.input_size;
  // Weights, gradients and the two Adam moments: 4 floats per parameter.
  return images * pixels * static_cast<uint64_t>(config.width) * 128 +
         static_cast<uint64_t>(parameters) * 4 * sizeof(float);
}

std::string Trainer::step_description(const TrainingConfig& config) {
  int64_t images = 0;
  for (const DataSource& s : config.sources) images += s.batch;
  return "batch " + std::to_string(images) + " of " + std::to_string(config.input_size) + "x" +
         std::to_string(config.input_size) + " images at width " + std::to_string(config.width);
}

int64_t Trainer::parameter_estimate(const TrainingConfig& config) {
  return int64_t{225} * config.width * config.width;
}

int64_t Trainer::parameter_count() const {
  int64_t count = 0;
  for (const auto& entry : network_->parameters()) count += entry.second.value().numel();
  return count;
}

void Trainer::set_communicator(Communicator& comm) {
  // A rank without rows would run its network on an empty batch while the others wait in the
  // batch-norm sums: every rank refuses alike, before any step.
  for (const DataSource& s : config_.sources)
    check(s.batch >= comm.size(), "source '", s.name, "' of '", config_.path, "' has batch ",
          s.batch, ", fewer rows than the ", comm.size(), " ranks of this job (mpirun -np ",
          comm.size(), "): every rank takes rows of each global batch (docs/distributed.md); "
          "set its batch to at least ", comm.size(), " or run fewer ranks");
  comm_ = &comm;
  synced_batch_norm_ = comm.size() > 1;
  if (synced_batch_norm_)
    ag::set_batch_norm_statistics_sum([c = &comm](std::vector<double>& v) { c->allreduce_sum(v); });
  else
    ag::set_batch_norm_statistics_sum({});
}

void Trainer::allreduce_gradients() {
  std::vector<std::pair<std::string, ag::Variable>> params = network_->parameters();
  std::vector<float> bucket;
  std::vector<const ag::Variable*> members;
  auto flush = [&] {
    if (members.empty()) return;
    comm_->allreduce_sum(bucket.data(), static_cast<int64_t>(bucket.size()));
    size_t at = 0;
    for (const ag::Variable* p : members) {
      const int64_t n = p->grad().numel();
      p->grad().copy_from_host(std::vector<float>(bucket.begin() + at, bucket.begin() + at + n));
      at += n;
    }
    bucket.clear();
    members.clear();
  };
  for (const auto& entry : params) {
    const ag::Variable& p = entry.second;
    // Every rank builds the same graph, so a parameter no term reaches (e.g. the light branch
    // without a light term) lacks a gradient on all of them alike.
    if (!p.has_grad()) continue;
    const std::vector<float> g = p.grad().to_host();
    if (!bucket.empty() && static_cast<int64_t>(bucket.size() + g.size()) > kBucketFloats) flush();
    bucket.insert(bucket.end(), g.begin(), g.end());
    members.push_back(&p);
  }
  flush();
}

Trainer::Trainer(Backend& backend, TrainingConfig config, std::shared_ptr<NetworkPlugin> network,
                 std::shared_ptr<RendererPlugin> renderer,
                 std::vector<std::shared_ptr<LossPlugin>> losses)
    : backend_(backend),
      config_(std::move(config)),
      network_(std::move(network)),
      renderer_(std::move(renderer)),
      losses_(std::move(losses)) {
  std::vector<LossTermInfo> available;
  for (const auto& plugin : losses_)
    for (const LossTermInfo& t : plugin->terms()) available.push_back(t);
  check_terms(config_, available);
  for (const DataSource& s : config_.sources) {
    auto source = std::make_unique<Source>();
    source->config = &s;
    for (const WeightedTerm& t : s.terms) {
      LossPlugin* provider = nullptr;
      for (const auto& plugin : losses_)
        for (const LossTermInfo& info : plugin->terms())
          if (!provider && info.name == t.name) provider = plugin.get();
      source->terms.emplace_back(&t, provider);  // check_terms() found every one
    }
    sources_.push_back(std::move(source));
  }
  network_->build(backend_, NetworkConfig{config_.width, config_.input_size, config_.input_prior});
  network_->init_random(config_.seed);
  AdamParams p;
  p.lr = static_cast<float>(config_.learning_rate);
  p.beta1 = static_cast<float>(config_.beta1);
  p.beta2 = static_cast<float>(config_.beta2);
  p.eps = static_cast<float>(config_.epsilon);
  optimizer_ = std::make_unique<AdamOptimizer>(network_->parameters(), p);
}

Trainer::~Trainer() {
  if (synced_batch_norm_) ag::set_batch_norm_statistics_sum({});
}

void Trainer::restore(const std::string& checkpoint_path) {
  const CheckpointState s = read_checkpoint_state(checkpoint_path);
  auto prior = [](const std::string& p) { return p.empty() ? std::string() : " with input prior " + p; };
  check(s.architecture == config_.network && s.network.width == config_.width &&
            s.network.input_size == config_.input_size && s.network.input_prior == config_.input_prior,
        "checkpoint '", checkpoint_path, "' holds a ", s.architecture, " of width ",
        s.network.width, " and input ", s.network.input_size, prior(s.network.input_prior), ", but '",
        config_.path, "' asks for a ", config_.network, " of width ", config_.width, " and input ",
        config_.input_size, prior(config_.input_prior));
  // A damaged step count would be believed: a negative one rewrites the log to nothing, a huge
  // one ends the run at once claiming it trained.
  check(s.step >= 0 && s.step <= config_.steps, "checkpoint '", checkpoint_path,
        "' says it is at step ", s.step, ", outside 0 .. ", config_.steps, " (the steps of '",
        config_.path, "'); ", s.step > config_.steps && s.step <= (int64_t{1} << 40)
            ? "pass --steps N with N >= that step to train further"
            : "the file is damaged: use an earlier copy or start the run afresh");
  step_ = load_checkpoint(checkpoint_path, *network_, *optimizer_).step;
  for (auto& source : sources_) source->reader.reset();
}

void Trainer::save(const std::string& checkpoint_path) const {
  // A checkpoint is never written with NaN or infinite weights: resuming it could not recover.
  auto check_finite = [&](const std::string& name, const Tensor& t) {
    for (const float v : t.to_host())
      if (!std::isfinite(v))
        throw TrainingDiverged("training diverged at step " + std::to_string(step_) +
                               ": the network's '" + name + "' holds a NaN or infinite value; " +
                               "no checkpoint was written and the last one is kept");
  };
  for (const auto& [name, p] : network_->parameters()) check_finite(name, p.value());
  for (const auto& [name, t] : network_->buffers()) check_finite(name, t);
  CheckpointState s;
  s.step = step_;
  s.seed = config_.seed;
  s.config_name = config_.name;
  s.architecture = config_.network;
  s.network = network_->config();
  save_checkpoint(checkpoint_path, *network_, *optimizer_, s);
}

StepRecord Trainer::step() {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  StepRecord record;
  record.step = step_ + 1;
  ag::Variable total;
  for (auto& source : sources_) {
    const auto wait = Clock::now();
    if (!source->reader) {
      DatasetReaderOptions o = reader_options(config_, *source->config, false);
      o.start_batch = step_;
      source->reader = std::make_unique<DatasetReader>(backend_, o);
      check(source->reader->width() == config_.input_size &&
                source->reader->height() == config_.input_size,
            "source '", source->config->name, "' holds ", source->reader->width(), "x",
            source->reader->height(), " samples but the network takes ", config_.input_size, "x",
            config_.input_size, "; set network.input_size in '", config_.path, "'");
      const CropFraming framing = parse_framing(source->reader->framing(), "source '" + source->config->name + "'");
      check(framing == config_.framing, "source '", source->config->name, "' holds samples framed '",
            framing_text(framing), "' but network.framing in '", config_.path, "' is '",
            framing_text(config_.framing), "'; make the samples with the same --framing or set network.framing");
    }
    const bool parallel = comm_->size() > 1;
    SyntheticBatch batch = source->reader->next();
    const int64_t global_images = batch.image.shape().n();
    if (parallel) batch = rank_slice(batch, comm_->rank(), comm_->size());
    record.seconds_data += std::chrono::duration<double>(Clock::now() - wait).count();
    record.images += global_images;
    // This rank's share of each normaliser: masked pixels (masked MSE) and images (light).
    double pixel_share = 1.0, image_share = 1.0;
    if (parallel) {
      std::vector<double> counts{mask_total(batch.mask), double(batch.image.shape().n())};
      const std::vector<double> local = counts;
      comm_->allreduce_sum(counts);
      pixel_share = counts[0] > 0 ? local[0] / counts[0] : 0.0;
      image_share = local[1] / counts[1];
    }
    const int source_index = static_cast<int>(&source - sources_.data());
    const int64_t first_row = parallel ? rank_rows(global_images, comm_->rank(), comm_->size()).first : 0;
    mirror_some_rows(batch, config_.seed, step_, source_index, source->config->mirror_fraction, first_row);
    relight_some_rows(batch, config_.seed, step_, source_index, source->config->relight_fraction, first_row,
                      source->config->relight_light == "hard" ? RelightLight::kHard : RelightLight::kSh);
    const Tensor input = grey_some_rows(batch.network_input(), config_.seed, step_, source_index,
                                        source->config->grey_fraction, first_row);
    const NetworkOutputs out = network_->forward(ag::Variable(input), true);
    // The light feeds the renderer, which would refuse it with a message naming neither the
    // step nor the cause: a non-finite light is divergence (the batch itself was checked when
    // it was read).
    for (const float v : out.light.value().to_host())
      if (!std::isfinite(v))
        throw TrainingDiverged("training diverged at step " + std::to_string(record.step) +
                               ": the network's light output for source '" +
                               source->config->name + "' is not finite (the weights hold NaN " +
                               "or infinite values); the last checkpoint is kept");
    const LossTargets targets = targets_of(batch, *source->config);
    std::vector<ag::Variable> values;
    std::vector<double> shares, totals;
    for (const auto& [term, plugin] : source->terms) {
      values.push_back(plugin->evaluate(term->name, out, targets, *renderer_));
      shares.push_back(plugin_term_is_per_image(*plugin, term->name) ? image_share : pixel_share);
      totals.push_back(shares.back() * values.back().value().to_host()[0]);
    }
    if (parallel) comm_->allreduce_sum(totals);  // every rank sees the global batch's values
    for (size_t i = 0; i < source->terms.size(); ++i) {
      const WeightedTerm* term = source->terms[i].first;
      const double v = totals[i];
      const std::string label = source->config->name + "/" + term->name;
      if (!std::isfinite(v))
        throw TrainingDiverged("training diverged at step " + std::to_string(record.step) +
                               ": loss term '" + label + "' is " + std::to_string(v) +
                               "; the weights were not updated and the last checkpoint is kept");
      record.terms.emplace_back(label, v);
      record.total += term->weight * v;
      if (term->weight == 0.0) continue;
      const ag::Variable weighted =
          ag::scale(values[i], static_cast<float>(term->weight * (parallel ? shares[i] : 1.0)));
      total = total.defined() ? ag::add(total, weighted) : weighted;
    }
  }
  if (total.defined()) total.backward();
  if (comm_->size() > 1) {
    const auto reduce = Clock::now();
    allreduce_gradients();
    record.seconds_allreduce = std::chrono::duration<double>(Clock::now() - reduce).count();
  }
  optimizer_->step();
  ++step_;
  record.seconds_total = std::chrono::duration<double>(Clock::now() - start).count();
  return record;
}

ValidationRecord Trainer::validate() {
  ValidationRecord r;
  r.step = step_;
  const DataSource* labelled = nullptr;
  for (const DataSource& s : config_.sources)
    if (!labelled && s.kind != "real") labelled = &s;
  if (!labelled || config_.validation_holdout_every == 0) return r;
  DatasetReader reader(backend_, reader_options(config_, *labelled, true));
  double sum = 0.0, sum_sq = 0.0;
  const double kDegrees = 180.0 / kPi;
  for (int b = 0; b < config_.validation_batches; ++b) {
    const SyntheticBatch batch = reader.next();
    if (b > 0 && batch.epoch > 0) break;  // the validation part is smaller than asked for
    const NetworkOutputs out = network_->forward(ag::Variable(batch.network_input()), false);
    const std::vector<float> pred = out.normal.value().to_host(), target = batch.normal.to_host(),
                             mask = batch.mask.to_host();
    const Shape& s = batch.normal.shape();
    const int64_t plane = s.h() * s.w();
    for (int64_t n = 0; n < s.n(); ++n)
      for (int64_t p = 0; p < plane; ++p) {
        if (mask[n * plane + p] <= 0.5f) continue;
        double dot = 0.0, lp = 0.0, lt = 0.0;
        for (int c = 0; c < 3; ++c) {
          const double a = pred[(n * 3 + c) * plane + p], t = target[(n * 3 + c) * plane + p];
          dot += a * t;
          lp += a * a;
          lt += t * t;
        }
        const double cosine = std::fmax(-1.0, std::fmin(1.0, dot / std::sqrt(lp * lt + 1e-30)));
        const double angle = std::acos(cosine) * kDegrees;
        sum += angle;
        sum_sq += angle * angle;
        ++r.pixels;
      }
  }
  if (r.pixels > 0) {
    r.normal_error_mean_deg = sum / r.pixels;
    r.normal_error_std_deg =
        std::sqrt(std::fmax(0.0, sum_sq / r.pixels - r.normal_error_mean_deg * r.normal_error_mean_deg));
  }
  return r;
}

}  // namespace facetool
