// Training-step benchmark: the Trainer on generated samples, and the loss terms timed alone.
#include "apps/facetool/bench/train_benchmarks.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <random>
#include <sstream>
#include <unistd.h>

#include "core/autograd/functions.h"
#include "libs/synth/synth_sample.h"
#include "libs/distributed/communicator.h"
#include "libs/train/trainer.h"

namespace facetool {
namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Samples with a lit sphere's labels: a disc mask, sphere normals, smooth albedo, open
// visibility, a random light; the image is noise (the benchmark needs shapes, not meaning).
void write_bench_samples(const std::string& dir, int count, int size) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < count; ++i) {
    SynthSample s;
    s.width = s.height = size;
    const size_t plane = s.plane();
    s.image.resize(3 * plane);
    for (float& v : s.image) v = u(rng);
    s.albedo.assign(3 * plane, 0.0f);
    s.normal.assign(3 * plane, 0.0f);
    s.mask.assign(plane, 0.0f);
    s.visibility.assign(9 * plane, 0.0f);
    s.depth.assign(plane, 0.0f);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const double nx = (x + 0.5) / size * 2.0 - 1.0, ny = 1.0 - (y + 0.5) / size * 2.0;
        const double r2 = nx * nx + ny * ny;
        if (r2 >= 0.8) continue;
        const size_t p = static_cast<size_t>(y) * size + x;
        s.mask[p] = 1.0f;
        s.normal[p] = static_cast<float>(nx);
        s.normal[plane + p] = static_cast<float>(ny);
        s.normal[2 * plane + p] = static_cast<float>(std::sqrt(1.0 - r2));
        for (int c = 0; c < 3; ++c) s.albedo[c * plane + p] = 0.3f + 0.4f * u(rng);
        s.visibility[p] = 3.5449077f;  // 2 sqrt(pi): nothing occluded
        s.depth[p] = 5.0f;
      }
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 9; ++k) s.light[c * 9 + k] = k == 0 ? 1.0 + u(rng) : 0.4 * (u(rng) - 0.5);
    s.index = i;
    s.light_source = "bench";
    s.shape = "bench sphere";
    write_synth_sample(dir + "/" + sample_file_name(i), s);
  }
}

TrainingConfig stage1_config(const std::string& dir, int width, int size, int batch) {
  TrainingConfig c;
  c.path = "(bench)";
  c.name = "bench-stage1";
  c.width = width;
  c.input_size = size;
  c.steps = 1 << 30;
  c.validation_holdout_every = 0;
  DataSource s;
  s.name = "synthetic";
  s.kind = "synthetic";
  s.directory = dir;
  s.batch = batch;
  s.terms = {{"recon_albedo", 1.0}, {"recon_normal", 0.2}, {"recon_visibility", 0.2},
             {"recon_light", 0.01}, {"albedo", 1.0},       {"normal", 0.2},
             {"visibility", 0.2},   {"light", 0.01}};
  c.sources.push_back(s);
  return c;
}

}  // namespace

void run_train_benchmarks(const std::function<std::shared_ptr<NetworkPlugin>()>& make_network,
                          std::shared_ptr<RendererPlugin> renderer,
                          std::shared_ptr<LossPlugin> losses, Backend& backend,
                          const TrainBenchOptions& o, std::ostream& out) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("facetool-bench-train-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  struct Cleanup {
    fs::path p;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  } cleanup{dir};
  write_bench_samples(dir.string(), 2 * o.batch, o.input_size);
  // Under mpirun the ranks split each batch of o.batch images (docs/distributed.md); rank 0
  // prints, the others stay silent.
  const std::unique_ptr<Communicator> comm = make_communicator();
  std::ostringstream silent;
  std::ostream& print = comm->rank() == 0 ? out : silent;

  char line[256];
  print << "full stage-1 step (batch " << o.batch << ", " << o.input_size << "x" << o.input_size
        << ", 8 terms, Adam) on " << backend.name() << ", " << comm->describe() << "\n";
  std::snprintf(line, sizeof line, "%6s %10s %10s %14s %12s %12s %12s\n", "width", "step ms",
                "images/s", "losses+render", "data wait", "network+Adam", "allreduce");
  print << line;
  for (int width : o.widths) {
    const TrainingConfig config = stage1_config(dir.string(), width, o.input_size, o.batch);
    Trainer trainer(backend, config, make_network(), renderer, {losses});
    trainer.set_communicator(*comm);
    trainer.step();  // warm-up: kernels compiled, buffers cached, reader primed
    std::vector<double> step_s, wait_s, reduce_s;
    for (int r = 0; r < o.repeats; ++r) {
      backend.synchronize();
      const StepRecord rec = trainer.step();
      backend.synchronize();
      step_s.push_back(rec.seconds_total);
      wait_s.push_back(rec.seconds_data);
      reduce_s.push_back(rec.seconds_allreduce);
    }
    // The eight terms alone on outputs of the same shapes: forward, backward to the outputs.
    const NetworkOutputs shapes = trainer.network().forward(
        ag::Variable(Tensor::zeros(backend, Shape{o.batch, 3, o.input_size, o.input_size})), false);
    DatasetReaderOptions ro;
    ro.directory = dir.string();
    ro.batch_size = o.batch;
    DatasetReader reader(backend, ro);
    const SyntheticBatch batch = reader.next();
    LossTargets targets{batch.image, batch.albedo, batch.normal, batch.visibility, batch.light, batch.mask};
    std::vector<double> loss_s;
    for (int r = 0; r < o.repeats + 1; ++r) {
      NetworkOutputs leaf{ag::Variable(shapes.albedo.value(), true),
                          ag::Variable(shapes.normal.value(), true),
                          ag::Variable(shapes.visibility.value(), true),
                          ag::Variable(shapes.light.value(), true)};
      backend.synchronize();
      const auto start = std::chrono::steady_clock::now();
      ag::Variable total;
      for (const WeightedTerm& t : config.sources[0].terms) {
        const ag::Variable v =
            ag::scale(losses->evaluate(t.name, leaf, targets, *renderer), static_cast<float>(t.weight));
        total = total.defined() ? ag::add(total, v) : v;
      }
      total.backward();
      backend.synchronize();
      if (r > 0)
        loss_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    const double step = median(step_s), wait = median(wait_s), loss = median(loss_s);
    const double reduce = median(reduce_s);
    std::snprintf(line, sizeof line,
                  "%6d %10.1f %10.1f %8.1f (%3.0f%%) %6.1f (%2.0f%%) %7.1f (%2.0f%%) %7.1f (%2.0f%%)\n",
                  width, step * 1e3, o.batch / step, loss * 1e3, 100.0 * loss / step, wait * 1e3,
                  100.0 * wait / step, (step - loss - wait) * 1e3,
                  100.0 * (step - loss - wait) / step, reduce * 1e3, 100.0 * reduce / step);
    print << line << std::flush;
  }
}

}  // namespace facetool
