// `bench conv`: every cpu convolution algorithm on the network's layer shapes, GFLOP/s, winners.
#include "apps/facetool/bench/conv_benchmarks.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <random>

#include "backends/cpu/cpu_backend_impl.h"
#include "backends/cpu/cpu_conv_choice.h"
#include "backends/cpu/cpu_epilogue.h"
#include "core/util/cpu_time.h"
#include "core/util/error.h"

namespace facetool {
namespace {

struct Layer {
  const char* name;
  int64_t in, out, kernel, stride, size, count;  // count: how many such layers per forward
};

// The paper network's convolutions (plugins/paper_network) at width c and input s.
std::vector<Layer> network_layers(int64_t c, int64_t s) {
  return {{"encoder.layer1 7x7", 3, c / 2, 7, 1, s, 1},
          {"encoder.layer2 3x3", c / 2, c, 3, 1, s, 1},
          {"encoder.down 3x3/2", c, c, 3, 2, s, 1},
          {"residual 3x3", c, c, 3, 1, s / 2, 20},
          {"decoder.layer1 3x3", c, c, 3, 1, s, 2},
          {"decoder.layer2 3x3", c, c / 2, 3, 1, s, 2},
          {"decoder.out 1x1 (shape)", c / 2, 12, 1, 1, s, 1},
          {"decoder.out 1x1 (albedo)", c / 2, 3, 1, 1, s, 1},
          {"light.layer1 1x1", 3 * c, c, 1, 1, s / 2, 1}};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

void run_conv_benchmarks(Backend& backend, const ConvBenchOptions& options, std::ostream& out) {
  auto* cpu_backend = dynamic_cast<cpu::CpuBackend*>(&backend);
  check(cpu_backend != nullptr, "bench conv measures the cpu backend's convolution algorithms; ",
        "run it with --backend cpu");
  out << "convolution algorithms on " << backend.device_description() << ", width "
      << options.width << ", input " << options.input_size << "x" << options.input_size
      << ", median of " << options.repeats << " (ms per call, GFLOP/s; * = fastest)\n";
  char line[256];
  std::snprintf(line, sizeof line, "%-26s %5s %-22s %10s %10s %10s %10s  %s\n", "layer", "batch",
                "shape", "im2col", "winograd", "dnnl", "direct",
                "fastest: GFLOP/s, and per core of CPU time");
  out << line;
  std::vector<std::pair<std::string, cpu::ConvAlgorithm>> winners;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> dist(-1.0f, 1.0f);
  for (const int64_t batch : options.batches) {
    double total_best = 0.0, total_best_cpu = 0.0, total_default = 0.0, total_flops = 0.0;
    for (const Layer& layer : network_layers(options.width, options.input_size)) {
      cpu::ConvGeometry g;
      g.channels = layer.in;
      g.height = g.width = layer.size;
      g.kernel = layer.kernel;
      g.stride = layer.stride;
      g.pad = layer.kernel / 2;
      g.out_height = g.out_width = (layer.size + 2 * g.pad - layer.kernel) / layer.stride + 1;
      std::vector<float> x(static_cast<size_t>(batch * layer.in * layer.size * layer.size));
      std::vector<float> w(static_cast<size_t>(layer.out * layer.in * layer.kernel * layer.kernel));
      std::vector<float> y(static_cast<size_t>(batch * layer.out * g.pixels()));
      for (float& v : x) v = dist(rng);
      for (float& v : w) v = dist(rng);
      const double flops = 2.0 * batch * layer.out * g.pixels() * g.rows();
      double times[4] = {0, 0, 0, 0}, cpu_times[4] = {0, 0, 0, 0};  // by ConvAlgorithm
      double best = 1e30;
      cpu::ConvAlgorithm best_algorithm = cpu::ConvAlgorithm::Im2col;
      for (cpu::ConvAlgorithm a : cpu::applicable_conv_algorithms(g, layer.out)) {
        std::vector<double> runs, cpu_runs;
        bool ran = true;
        for (int r = 0; r <= options.repeats && ran; ++r) {
          const double cpu0 = process_cpu_seconds();
          const auto start = std::chrono::steady_clock::now();
          ran = cpu_backend->convolve_with(a, g, batch, layer.out, x.data(), w.data(), y.data(),
                                           nullptr);
          const double s =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          if (r > 0) {  // run 0 warms caches and creates oneDNN's primitive
            runs.push_back(s);
            cpu_runs.push_back(process_cpu_seconds() - cpu0);
          }
        }
        if (!ran) continue;
        const double t = median(runs);
        times[static_cast<int>(a)] = t;
        cpu_times[static_cast<int>(a)] = median(cpu_runs);
        if (t < best) {
          best = t;
          best_algorithm = a;
        }
      }
      winners.emplace_back(cpu::conv_shape_key(g, batch, layer.out), best_algorithm);
      const double default_time = times[static_cast<int>(cpu::default_conv_algorithm(g, layer.out))];
      total_best += layer.count * best;
      total_best_cpu += layer.count * cpu_times[static_cast<int>(best_algorithm)];
      total_default += layer.count * default_time;
      total_flops += layer.count * flops;
      auto cell = [&](int a) {
        char text[32];
        if (times[a] <= 0) return std::string("-");
        std::snprintf(text, sizeof text, "%.3f%s", 1e3 * times[a],
                      static_cast<int>(best_algorithm) == a ? "*" : "");
        return std::string(text);
      };
      char shape[64];
      std::snprintf(shape, sizeof shape, "%lldx%lld %lld->%lld", static_cast<long long>(layer.size),
                    static_cast<long long>(layer.size), static_cast<long long>(layer.in),
                    static_cast<long long>(layer.out));
      std::snprintf(line, sizeof line, "%-26s %5lld %-22s %10s %10s %10s %10s  %.1f, %.1f\n",
                    layer.name, static_cast<long long>(batch), shape, cell(0).c_str(),
                    cell(1).c_str(), cell(2).c_str(), cell(3).c_str(), flops / best / 1e9,
                    flops / cpu_times[static_cast<int>(best_algorithm)] / 1e9);
      out << line;
    }
    std::snprintf(line, sizeof line,
                  "all convolutions, batch %lld: %.3f GFLOP/image; fastest per layer %.2f ms/image "
                  "(%.1f GFLOP/s; %.2f CPU ms/image, %.1f GFLOP/s per core), default rule %.2f "
                  "ms/image\n",
                  static_cast<long long>(batch), total_flops / batch / 1e9,
                  1e3 * total_best / batch, total_flops / total_best / 1e9,
                  1e3 * total_best_cpu / batch, total_flops / total_best_cpu / 1e9,
                  1e3 * total_default / batch);
    out << line;
  }
  if (options.save) {
    cpu::save_conv_choices(winners);
    out << "saved the fastest algorithm of each shape to " << cpu::conv_cache_path()
        << " (machine " << cpu::conv_machine_name() << ")\n";
  }
  out << std::flush;
}

}  // namespace facetool
