// OpenclBackend's Winograd F(4x4, 3x3) path: kernels/winograd.cl transforms around CLBlast GEMMs.
#include "backends/opencl/ops_winograd.h"

#include <algorithm>

#include "backends/opencl/opencl_backend.h"

namespace facetool::opencl {
namespace {

const char* kWinograd = "winograd.cl";
constexpr int64_t kPoints = 36;  // transformed values per 4x4 tile (6x6)

// The 4x4 tiles of an H x W image and how many images one chunk transforms at once: the
// transformed inputs and products ([36][channels][tiles] each) stay within 64 Mi floats.
struct Tiling {
  int64_t tiles_x, tiles_per_image, chunk;
  Tiling(int64_t batch, int64_t height, int64_t width, int64_t channels) {
    tiles_x = (width + 3) / 4;
    tiles_per_image = tiles_x * ((height + 3) / 4);
    const int64_t max_floats = int64_t(64) << 20;
    chunk = std::clamp<int64_t>(max_floats / (kPoints * channels * tiles_per_image), 1, batch);
  }
};

}  // namespace

bool winograd_applicable(int64_t kernel, int64_t stride, int64_t pad, int64_t in_channels,
                         int64_t out_channels, bool same_size) {
  return kernel == 3 && stride == 1 && pad == 1 && same_size && in_channels >= 32 &&
         out_channels >= 32;
}

void winograd_convolve(OpenclBackend& be, const WinogradProblem& p, const Tensor& x,
                       const Tensor& w, bool flipped, const Tensor* bias, const Tensor& y,
                       bool accumulate) {
  const int64_t I = p.in_channels, O = p.out_channels;
  const Tiling tiling(p.batch, p.height, p.width, std::max(I, O));
  Tensor u = be.scratch(kPoints * O * I);
  run_nd(be, kWinograd, "winograd_weights", {I, O}, w, u, O, I, flipped);
  const int64_t max_tiles = tiling.chunk * tiling.tiles_per_image;
  Tensor v = be.scratch(kPoints * I * max_tiles);
  Tensor m = be.scratch(kPoints * O * max_tiles);
  for (int64_t n0 = 0; n0 < p.batch; n0 += tiling.chunk) {
    const int64_t T = std::min(tiling.chunk, p.batch - n0) * tiling.tiles_per_image;
    run_nd(be, kWinograd, "winograd_input", {T, I}, x, v, n0, T, I, p.height, p.width,
           tiling.tiles_x, tiling.tiles_per_image);
    // m[xi] [O, T] = u[xi] [O, I] x v[xi] [I, T]
    for (int64_t xi = 0; xi < kPoints; ++xi)
      be.gemm().run(false, false, O, T, I, 1.0f, device_memory(u), xi * O * I, I,
                    device_memory(v), xi * I * T, T, 0.0f, device_memory(m), xi * O * T, T);
    run_nd(be, kWinograd, "winograd_output", {T, O}, m, y, bias ? *bias : m, bias != nullptr,
           accumulate, n0, T, O, p.height, p.width, tiling.tiles_x, tiling.tiles_per_image);
  }
}

void winograd_weight_gradient(OpenclBackend& be, const WinogradProblem& p, const Tensor& x,
                              const Tensor& dy, const Tensor& dw, bool accumulate) {
  const int64_t I = p.in_channels, O = p.out_channels;
  const Tiling tiling(p.batch, p.height, p.width, std::max(I, O));
  const int64_t max_tiles = tiling.chunk * tiling.tiles_per_image;
  Tensor v = be.scratch(kPoints * I * max_tiles);
  Tensor m = be.scratch(kPoints * O * max_tiles);
  Tensor sums = be.scratch(kPoints * O * I);
  for (int64_t n0 = 0; n0 < p.batch; n0 += tiling.chunk) {
    const int64_t T = std::min(tiling.chunk, p.batch - n0) * tiling.tiles_per_image;
    run_nd(be, kWinograd, "winograd_input", {T, I}, x, v, n0, T, I, p.height, p.width,
           tiling.tiles_x, tiling.tiles_per_image);
    run_nd(be, kWinograd, "winograd_output_gradient", {T, O}, dy, m, n0, T, O, p.height,
           p.width, tiling.tiles_x, tiling.tiles_per_image);
    // sums[xi] [O, I] (+)= m[xi] [O, T] x v[xi]^T [T, I]
    const float beta = n0 == 0 ? 0.0f : 1.0f;
    for (int64_t xi = 0; xi < kPoints; ++xi)
      be.gemm().run(false, true, O, I, T, 1.0f, device_memory(m), xi * O * T, T,
                    device_memory(v), xi * I * T, T, beta, device_memory(sums), xi * O * I, I);
  }
  run_nd(be, kWinograd, "winograd_weight_gradient", {I, O}, sums, dw, O, I, accumulate);
}

}  // namespace facetool::opencl
