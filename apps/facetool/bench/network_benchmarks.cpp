// Network benchmarks: timed forward passes and training steps with medians over repeats.
#include "apps/facetool/bench/network_benchmarks.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <functional>
#include <random>
#include <set>

#include "backends/cpu/cpu_conv_choice.h"
#include "core/util/cpu_time.h"
#include "core/autograd/functions.h"
#include "core/backend/backend.h"
#include "core/ops/ops.h"
#include "libs/train/adam_optimizer.h"

namespace facetool {
namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Tensor random_images(Backend& be, int batch, int size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(0.0f, 1.0f);
  std::vector<float> values(static_cast<size_t>(batch) * 3 * size * size);
  for (float& v : values) v = dist(rng);
  return Tensor::from_host(be, Shape{batch, 3, size, size}, values);
}

// CPU time of the whole process (all threads), in ms.
double process_cpu_ms() { return 1e3 * process_cpu_seconds(); }

// Wall-clock and process CPU milliseconds of one run. On a machine shared with other work the
// wall time also counts the time spent waiting for a core; the CPU time does not (facetool's
// threads sleep while they wait, so it is the work done).
struct Timing {
  double wall, cpu;
};

template <typename F>
Timing time_ms(Backend& be, F&& work) {
  be.synchronize();
  const double cpu0 = process_cpu_ms();
  const auto start = std::chrono::steady_clock::now();
  work();
  be.synchronize();
  const double wall =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return {wall, process_cpu_ms() - cpu0};
}

// Times the fused forward at `batch` with each candidate number of images per chunk, in
// alternated rounds, prints one line per candidate and records the fastest for this machine.
void choose_fused_chunk(int batch, int repeats,
                        const std::function<Timing()>& forward_ms, std::ostream& out) {
  // The activation size the network asks the backend about: the first forward records it.
  forward_ms();
  const int64_t bytes = cpu::last_fused_chunk_request();
  if (bytes <= 0 || batch < 2) {
    out << "fused chunk: nothing to choose (the network asked for no chunk at batch " << batch << ")\n";
    return;
  }
  const int64_t rule = cpu::default_fused_chunk(bytes, batch);
  std::set<int64_t> distinct;
  for (int64_t images : {int64_t{1}, rule, 2 * rule, int64_t{batch}}) distinct.insert(std::min<int64_t>(images, batch));
  const std::vector<int64_t> candidates(distinct.begin(), distinct.end());
  std::vector<std::vector<double>> wall(candidates.size()), cpu_ms(candidates.size());
  for (int r = 0; r <= repeats; ++r)
    for (size_t c = 0; c < candidates.size(); ++c) {
      cpu::set_fused_chunk_override(candidates[c]);
      const Timing t = forward_ms();
      if (r > 0) {
        wall[c].push_back(t.wall / batch);
        cpu_ms[c].push_back(t.cpu / batch);
      }
    }
  cpu::set_fused_chunk_override(std::nullopt);
  size_t best = 0;
  char line[256];
  for (size_t c = 0; c < candidates.size(); ++c) {
    if (median(wall[c]) < median(wall[best])) best = c;
    const std::string label = "fused forward, " + std::to_string(candidates[c]) + " a chunk" +
                              (candidates[c] == rule ? " (rule)" : candidates[c] == batch ? " (whole)" : "");
    std::snprintf(line, sizeof line, "%-34s %8d %12.2f %10.2f %10s %12.2f\n", label.c_str(), batch,
                  median(wall[c]), 1000.0 / median(wall[c]), "", median(cpu_ms[c]));
    out << line;
  }
  const int64_t chosen = candidates[best];
  cpu::save_fused_chunk(bytes, chosen == batch ? 0 : chosen);
  out << "saved: " << (chosen == batch ? std::string("the whole batch") : std::to_string(chosen) + " image(s)")
      << " a chunk for " << bytes << "-byte activations, to " << cpu::conv_cache_path() << " (machine "
      << cpu::conv_machine_name() << ")\n"
      << std::flush;
}

}  // namespace

void run_network_benchmarks(NetworkPlugin& net, Backend& be, double gflop,
                            const NetworkBenchOptions& options, std::ostream& out) {
  const int size = net.config().input_size;
  char line[256];
  std::snprintf(line, sizeof line, "%-34s %8s %12s %10s %10s %12s\n", "benchmark", "batch",
                "ms/image", "images/s", "GFLOP/s", "cpu ms/image");
  out << "backend " << be.name() << " (" << be.device_description() << "), width "
      << net.config().width << ", input " << size << "x" << size << ", " << gflop
      << " GFLOP/image forward\n"
      << line;
  for (int batch : options.forward_batches) {
    ag::Variable images(random_images(be, batch, size, 1));
    auto forward_ms = [&] {
      return time_ms(be, [&] {
        NetworkOutputs o = net.forward(images, false);
        o.light.value().to_host();
      });
    };
    // With compare_plain, the same forward on the plain ops (no folding or fusion, the
    // reference path) alternates with the fused one (A B A B), so load changes hit both alike.
    std::vector<double> runs, plain, runs_cpu, plain_cpu;
    for (int r = 0; r <= options.repeats; ++r) {
      const Timing t = forward_ms();
      if (r > 0) {  // run 0 warms caches and compiles kernels
        runs.push_back(t.wall / batch);
        runs_cpu.push_back(t.cpu / batch);
      }
      if (!options.compare_plain) continue;
      ops::set_fused_paths_enabled(false);
      const Timing p = forward_ms();
      ops::set_fused_paths_enabled(true);
      if (r > 0) {
        plain.push_back(p.wall / batch);
        plain_cpu.push_back(p.cpu / batch);
      }
    }
    const double per_image = median(runs);
    std::snprintf(line, sizeof line, "%-34s %8d %12.2f %10.2f %10.1f %12.2f\n", "forward (eval)",
                  batch, per_image, 1000.0 / per_image, gflop / (per_image / 1000.0),
                  median(runs_cpu));
    out << line << std::flush;
    if (options.compare_plain) {
      const double plain_ms = median(plain);
      std::snprintf(line, sizeof line, "%-34s %8d %12.2f %10.2f %10.1f %12.2f\n",
                    "forward (eval, plain ops)", batch, plain_ms, 1000.0 / plain_ms,
                    gflop / (plain_ms / 1000.0), median(plain_cpu));
      out << line << std::flush;
    }
  }
  if (options.save_chunk && !options.forward_batches.empty()) {
    const int batch = *std::max_element(options.forward_batches.begin(), options.forward_batches.end());
    ag::Variable images(random_images(be, batch, size, 1));
    choose_fused_chunk(batch, options.repeats, [&] {
      return time_ms(be, [&] {
        NetworkOutputs o = net.forward(images, false);
        o.light.value().to_host();
      });
    }, out);
  }
  if (options.train_batch > 0) {
    const int batch = options.train_batch;
    ag::Variable images(random_images(be, batch, size, 2));
    AdamParams adam;
    adam.lr = 1e-4f;
    AdamOptimizer optimizer(net.parameters(), adam);
    std::vector<double> runs, runs_cpu;
    for (int r = 0; r <= options.repeats; ++r) {
      const Timing t = time_ms(be, [&] {
        NetworkOutputs o = net.forward(images, true);
        ag::Variable loss = ag::add(ag::add(ag::mean(o.albedo), ag::mean(o.normal)),
                                    ag::add(ag::mean(o.visibility), ag::mean(o.light)));
        loss.backward();
        optimizer.step();
        loss.value().to_host();
      });
      if (r > 0) {
        runs.push_back(t.wall);
        runs_cpu.push_back(t.cpu);
      }
    }
    const double step_ms = median(runs);
    std::snprintf(line, sizeof line, "%-34s %8d %12.2f %10.2f %10.1f %12.2f\n",
                  "training step (fwd+bwd+Adam)", batch, step_ms / batch, batch * 1000.0 / step_ms,
                  3.0 * gflop * batch / (step_ms / 1000.0), median(runs_cpu) / batch);
    out << line << std::flush;
  }
}

}  // namespace facetool
