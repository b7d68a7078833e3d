// Op micro-benchmarks: convolutions, batch norm and leaky ReLU at the paper's layer shapes.
#include "apps/facetool/bench/op_benchmarks.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool {
namespace {

struct ConvShape {
  const char* label;
  int64_t in_channels, out_channels, kernel, stride, height, width;  // input size
};

// The convolutions of the paper's network (input resolution 128x128, width 128).
const ConvShape kConvShapes[] = {
    {"conv 7x7 3->64 @128x128", 3, 64, 7, 1, 128, 128},
    {"conv 3x3 64->128 @128x128", 64, 128, 3, 1, 128, 128},
    {"conv 3x3 128->128 s2 128x128->64x64", 128, 128, 3, 2, 128, 128},
    {"conv 3x3 128->128 @64x64", 128, 128, 3, 1, 64, 64},
    {"conv 1x1 384->128 @64x64", 384, 128, 1, 1, 64, 64},
};

struct Row {
  std::string layer;
  int batch;
  const char* direction;
  double ms;
  double gflop;
};

// Median milliseconds of `repeats` runs of fn after one warm-up run.
double median_ms(Backend& backend, int repeats, const std::function<void()>& fn) {
  fn();
  backend.synchronize();
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    fn();
    backend.synchronize();
    times.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

Tensor uniform(Backend& backend, const Shape& shape, float value) {
  return Tensor::full(backend, shape, value);
}

void bench_conv(Backend& backend, const ConvShape& s, int batch, int repeats,
                std::vector<Row>& rows) {
  Tensor x = uniform(backend, Shape{batch, s.in_channels, s.height, s.width}, 0.5f);
  Tensor w = uniform(backend, Shape{s.out_channels, s.in_channels, s.kernel, s.kernel}, 0.01f);
  Tensor b = uniform(backend, Shape{s.out_channels}, 0.1f);
  Conv2dParams p;
  p.stride = static_cast<int>(s.stride);
  Tensor y = ops::conv2d(x, w, &b, p);
  const Shape& ys = y.shape();
  const double flops = 2.0 * batch * s.out_channels * s.in_channels * s.kernel * s.kernel *
                       ys.h() * ys.w();
  const double fwd = median_ms(backend, repeats, [&] { y = ops::conv2d(x, w, &b, p); });
  rows.push_back({s.label, batch, "forward", fwd, flops / 1e9});
  Tensor dy = uniform(backend, ys, 0.01f);
  Tensor dx = Tensor::empty(backend, x.shape());
  Tensor dw = Tensor::empty(backend, w.shape());
  Tensor db = Tensor::empty(backend, b.shape());
  // The two halves of the backward pass separately (each costs one forward's flops).
  const double bwd_dx = median_ms(backend, repeats, [&] {
    ops::conv2d_backward(x, w, dy, &dx, nullptr, nullptr, p, false);
  });
  rows.push_back({s.label, batch, "backward dx", bwd_dx, flops / 1e9});
  const double bwd_dw = median_ms(backend, repeats, [&] {
    ops::conv2d_backward(x, w, dy, nullptr, &dw, &db, p, false);
  });
  rows.push_back({s.label, batch, "backward dw+db", bwd_dw, flops / 1e9});
}

// Batch norm and leaky ReLU at 128x64x64; flop counts are nominal (per element: BN forward 6,
// backward 10; leaky ReLU 1 each way), as these layers are bound by memory traffic.
void bench_pointwise_layers(Backend& backend, int batch, int repeats, std::vector<Row>& rows) {
  const int64_t channels = 128;
  const Shape shape{batch, channels, 64, 64};
  const double elements = static_cast<double>(shape.numel());
  Tensor x = uniform(backend, shape, 0.3f);
  Tensor dy = uniform(backend, shape, 0.01f);
  Tensor dx = Tensor::empty(backend, shape);
  Tensor gamma = uniform(backend, Shape{channels}, 1.0f);
  Tensor beta = uniform(backend, Shape{channels}, 0.0f);
  Tensor running_mean = uniform(backend, Shape{channels}, 0.0f);
  Tensor running_var = uniform(backend, Shape{channels}, 1.0f);
  Tensor dgamma = Tensor::empty(backend, Shape{channels});
  Tensor dbeta = Tensor::empty(backend, Shape{channels});
  BatchNormParams bn;
  ops::BatchNormSaved saved;
  Tensor y = ops::batch_norm(x, gamma, beta, running_mean, running_var, bn, &saved);
  const char* bn_label = "batch norm (train) 128x64x64";
  rows.push_back({bn_label, batch, "forward", median_ms(backend, repeats, [&] {
                    y = ops::batch_norm(x, gamma, beta, running_mean, running_var, bn, &saved);
                  }),
                  6.0 * elements / 1e9});
  rows.push_back({bn_label, batch, "backward", median_ms(backend, repeats, [&] {
                    ops::batch_norm_backward(x, gamma, saved, dy, &dx, &dgamma, &dbeta, bn,
                                             false);
                  }),
                  10.0 * elements / 1e9});
  const char* relu_label = "leaky relu 128x64x64";
  rows.push_back({relu_label, batch, "forward",
                  median_ms(backend, repeats, [&] { y = ops::leaky_relu(x, 0.2f); }),
                  elements / 1e9});
  rows.push_back({relu_label, batch, "backward", median_ms(backend, repeats, [&] {
                    ops::leaky_relu_backward(x, 0.2f, dy, dx, false);
                  }),
                  elements / 1e9});
}

void print_row(std::ostream& out, const Row& r) {
  char line[256];
  std::snprintf(line, sizeof line, "%-38s %6d  %-20s %10.3f %10.1f", r.layer.c_str(), r.batch,
                r.direction, r.ms, r.gflop / (r.ms / 1e3));
  out << line << "\n";
}

}  // namespace

void run_op_benchmarks(Backend& backend, const std::vector<int>& batches, int repeats,
                       std::ostream& out) {
  check(repeats >= 1, "bench ops: repeats must be at least 1, got ", repeats);
  for (int batch : batches)
    check(batch >= 1, "bench ops: batch sizes must be at least 1, got ", batch);
  out << "op benchmarks on '" << backend.name() << "' (" << backend.device_description()
      << "), median of " << repeats << " runs after a warm-up\n"
      << "GFLOP/s counts a direct convolution's multiply-adds (2 FLOP each), also for layers "
         "computed with Winograd's fewer\n";
  char header[256];
  std::snprintf(header, sizeof header, "%-38s %6s  %-20s %10s %10s", "layer", "batch",
                "direction", "ms", "GFLOP/s");
  out << header << "\n";
  // Rows stream out as they are measured, except the headline row (3x3 128->128 forward at
  // batch 20), which is held back and printed last.
  const std::string headline_layer = "conv 3x3 128->128 @64x64";
  Row headline{};
  bool have_headline = false;
  for (int batch : batches) {
    std::vector<Row> rows;
    for (const ConvShape& s : kConvShapes) bench_conv(backend, s, batch, repeats, rows);
    bench_pointwise_layers(backend, batch, repeats, rows);
    for (const Row& r : rows) {
      if (r.layer == headline_layer && r.batch == 20 && std::string(r.direction) == "forward") {
        headline = r;
        have_headline = true;
        continue;
      }
      print_row(out, r);
    }
    out.flush();
  }
  if (have_headline) print_row(out, headline);
}

}  // namespace facetool
