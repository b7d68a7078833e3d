// The cpu backend's fused inference ops: convolution + epilogue by the chosen algorithm, and the
// eval-mode batch norm + leaky ReLU in one pass.
#include <algorithm>

#include "backends/cpu/cpu_backend_impl.h"
#include "backends/cpu/cpu_conv.h"
#include "backends/cpu/cpu_conv_choice.h"
#include "backends/cpu/cpu_epilogue.h"
#include "backends/cpu/cpu_weight_cache.h"
#include "backends/cpu/cpu_winograd.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {

bool CpuBackend::convolve_with(ConvAlgorithm algorithm, const ConvGeometry& g, int64_t batch,
                               int64_t out_channels, const float* x, const float* w, float* y,
                               const Epilogue* epilogue) {
  switch (algorithm) {
    case ConvAlgorithm::Im2col:
      im2col_convolve(g, batch, out_channels, x, w, nullptr, y, false, epilogue);
      return true;
    case ConvAlgorithm::Winograd: {
      if (!(g.kernel == 3 && g.stride == 1 && g.pad == 1 && g.out_height == g.height &&
            g.out_width == g.width))
        return false;
      // Inference calls a layer with the same weights again and again: transformed once.
      const auto transformed = cached_weight_transform(
          w, static_cast<size_t>(out_channels * g.rows()), winograd_weight_floats(g, out_channels),
          [&](const float* weights, float* out) {
            winograd_transform_weights(g, out_channels, weights, out);
          });
      winograd_convolve_transformed(g, batch, out_channels, x, transformed->data(), nullptr, y,
                                    false, epilogue);
      return true;
    }
    case ConvAlgorithm::Dnnl:
      return dnnl_convolve(g, batch, out_channels, x, w, y, epilogue);
    case ConvAlgorithm::Direct:
      return direct_convolve(g, batch, out_channels, x, w, y, epilogue);
  }
  return false;
}

int64_t CpuBackend::fused_batch_chunk(int64_t bytes_per_image, int64_t batch) {
  return chosen_fused_chunk(bytes_per_image, batch);
}

void CpuBackend::run_branches(int64_t batch, const std::vector<std::function<void()>>& branches) {
  // Batch 1 on two threads cuts each layer in two: about a hundred short jobs with a barrier
  // each, and every layer's input read by both cores. Two equal branches (the paper network's
  // albedo and shape halves: residual stack and decoder) on a thread each run their layers
  // whole, inline (parallel_for inside a parallel_for), with their activations in that core's
  // cache; their ops see one thread here (parallel_threads_here) and cut their tasks for one.
  const int64_t threads = parallel_thread_count();
  if (batch >= threads || static_cast<int64_t>(branches.size()) < threads) {
    Backend::run_branches(batch, branches);
    return;
  }
  parallel_for_each_item(static_cast<int64_t>(branches.size()),
                         [&](int64_t i) { branches[static_cast<size_t>(i)](); });
}

bool CpuBackend::conv2d_fused(const Tensor& x, const Tensor& w, const Tensor& y,
                              const Conv2dParams& p, const ConvEpilogue& e) {
  ConvGeometry g;
  g.channels = x.shape().c();
  g.height = x.shape().h();
  g.width = x.shape().w();
  g.kernel = w.shape().h();
  g.stride = p.stride;
  g.pad = p.effective_pad(g.kernel);
  g.out_height = y.shape().h();
  g.out_width = y.shape().w();
  const int64_t batch = x.shape().n();
  const int64_t out_channels = w.shape().n();
  Epilogue epilogue;
  epilogue.scale = e.scale ? ptr(*e.scale) : nullptr;
  epilogue.shift = e.shift ? ptr(*e.shift) : nullptr;
  epilogue.residual = e.residual ? ptr(*e.residual) : nullptr;
  epilogue.activation = e.activation;
  epilogue.slope = e.slope;
  epilogue.y2 = e.y2 ? ptr(*e.y2) : nullptr;
  epilogue.post_scale = e.post_scale ? ptr(*e.post_scale) : nullptr;
  epilogue.post_shift = e.post_shift ? ptr(*e.post_shift) : nullptr;
  epilogue.post_slope = e.post_slope;
  epilogue.out_channels = out_channels;
  epilogue.plane = g.pixels();
  const ConvAlgorithm chosen = chosen_conv_algorithm(g, batch, out_channels);
  if (convolve_with(chosen, g, batch, out_channels, ptr(x), ptr(w), ptr(y), &epilogue))
    return true;
  return convolve_with(ConvAlgorithm::Im2col, g, batch, out_channels, ptr(x), ptr(w), ptr(y),
                       &epilogue);
}

bool CpuBackend::channel_affine_leaky_relu(const Tensor& x, const Tensor& scale,
                                           const Tensor& shift, float slope, const Tensor& y) {
  const Shape& s = x.shape();
  const int64_t plane = s.h() * s.w();
  const float* px = ptr(x);
  const float* ps = ptr(scale);
  const float* pt = ptr(shift);
  float* py = ptr(y);
  // One task per (image, channel) plane, several planes per chunk when planes are small.
  parallel_for(s.n() * s.c(), std::max<int64_t>(1, kElementwiseGrain / plane),
               [&](int64_t begin, int64_t end) {
                 for (int64_t i = begin; i < end; ++i) {
                   const int64_t c = i % s.c();
                   const float a = ps[c], b = pt[c];
                   const float* __restrict in = px + i * plane;
                   float* __restrict out = py + i * plane;
                   for (int64_t j = 0; j < plane; ++j) {
                     const float v = a * in[j] + b;
                     out[j] = v > 0.0f ? v : slope * v;
                   }
                 }
               });
  return true;
}

}  // namespace facetool::cpu
