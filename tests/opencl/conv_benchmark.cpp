// Benchmark (not a test): GEMM and 3x3 128->128 convolution throughput on the opencl backend.
// Usage: opencl_conv_benchmark [device]   (FACETOOL_CLBLAST_DEFAULTS=1 for CLBlast's defaults)
#include <chrono>
#include <cstdio>
#include <exception>

#include "backends/opencl/opencl_backend.h"

using namespace facetool;

namespace {

double seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Mean wall time of `reps` calls after one warm-up, with clFinish around (PoCL events are
// unreliable for timing).
template <typename Fn>
double time_it(opencl::OpenclBackend& be, int reps, Fn fn) {
  fn();
  be.synchronize();
  const double start = seconds();
  for (int i = 0; i < reps; ++i) fn();
  be.synchronize();
  return (seconds() - start) / reps;
}

void run(const char* device) {
  const double start = seconds();
  opencl::OpenclBackend be(opencl::select_device(device));
  std::printf("%s\n%s\n", be.device_description().c_str(), be.gemm().tuning().c_str());
  const int64_t m = 128, n = 4096, k = 1152;
  Tensor a = Tensor::full(be, Shape{m, k}, 0.01f), b = Tensor::full(be, Shape{k, n}, 0.02f);
  Tensor c = Tensor::zeros(be, Shape{m, n});
  const double first = seconds();
  be.gemm().run(false, false, m, n, k, 1.0f, opencl::device_memory(a), 0, k,
                opencl::device_memory(b), 0, n, 0.0f, opencl::device_memory(c), 0, n);
  be.synchronize();
  std::printf("first GEMM call (CLBlast kernel build or cache load): %.2f s (%.2f s since start)\n",
              seconds() - first, seconds() - start);
  const double t_gemm = time_it(be, 5, [&] {
    be.gemm().run(false, false, m, n, k, 1.0f, opencl::device_memory(a), 0, k,
                  opencl::device_memory(b), 0, n, 0.0f, opencl::device_memory(c), 0, n);
  });
  std::printf("GEMM %lldx%lldx%lld: %.1f ms, %.1f GFLOP/s\n", (long long)m, (long long)n,
              (long long)k, t_gemm * 1e3, 2.0 * m * n * k / t_gemm * 1e-9);
  for (int64_t batch : {1, 20}) {
    Tensor x = Tensor::full(be, Shape{batch, 128, 64, 64}, 0.5f);
    Tensor w = Tensor::full(be, Shape{128, 128, 3, 3}, 0.01f);
    Tensor bias = Tensor::full(be, Shape{128}, 0.1f);
    Tensor y = Tensor::empty(be, Shape{batch, 128, 64, 64});
    Tensor dx = Tensor::empty(be, x.shape()), dw = Tensor::empty(be, w.shape());
    Tensor db = Tensor::empty(be, Shape{128});
    Conv2dParams p;
    const int reps = batch == 1 ? 5 : 1;
    const double fwd = time_it(be, reps, [&] { be.conv2d(x, w, &bias, y, p); });
    const double bwd =
        time_it(be, reps, [&] { be.conv2d_backward(x, w, y, &dx, &dw, &db, p, false); });
    const double gflop = 2.0 * batch * 128 * 64 * 64 * 128 * 9 * 1e-9;
    std::printf("conv 3x3 128->128 64x64 batch %lld: forward %.1f ms (%.1f GFLOP/s), backward "
                "dx+dw+dbias %.1f ms (%.1f GFLOP/s)\n",
                (long long)batch, fwd * 1e3, gflop / fwd, bwd * 1e3, 2 * gflop / bwd);
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    run(argc > 1 ? argv[1] : "");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
