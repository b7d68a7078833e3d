// 2-D convolution on the cpu: im2col over blocks of output pixels + SGEMM, and its backward.
#include <algorithm>
#include <cstring>
#include <vector>

#include "backends/cpu/cpu_backend_impl.h"
#include "backends/cpu/cpu_conv.h"
#include "backends/cpu/cpu_im2col.h"
#include "backends/cpu/cpu_task_split.h"
#include "backends/cpu/cpu_winograd.h"
#include "backends/cpu/cpu_workspace.h"
#include "backends/cpu/gemm.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {
namespace {

// im2col blocks hold about this many floats (2 MiB, about L2): 448 pixels for K = 1152.
constexpr int64_t kForwardBlockFloats = 512 * 1024;
// The weight gradient's GEMM sums over the block's pixels: longer blocks mean fewer passes over dw.
constexpr int64_t kWeightGradBlockFloats = 1024 * 1024;

ConvGeometry geometry(const Tensor& x, const Tensor& w, const Tensor& y_or_dy,
                      const Conv2dParams& p) {
  ConvGeometry g;
  g.channels = x.shape().c();
  g.height = x.shape().h();
  g.width = x.shape().w();
  g.kernel = w.shape().h();
  g.stride = p.stride;
  g.pad = p.effective_pad(g.kernel);
  g.out_height = y_or_dy.shape().h();
  g.out_width = y_or_dy.shape().w();
  return g;
}

// A 1x1, stride-1, unpadded convolution reads x directly as its im2col matrix.
bool is_pointwise(const ConvGeometry& g) {
  return g.kernel == 1 && g.stride == 1 && g.pad == 0;
}

// Pixels per block: about `block_floats` im2col values, a multiple of 16, at most all pixels.
int64_t pixel_block(const ConvGeometry& g, int64_t block_floats) {
  int64_t block = block_floats / g.rows() / 16 * 16;
  return std::clamp<int64_t>(block, 16, g.pixels());
}

int64_t ceil_div(int64_t a, int64_t b) { return (a + b - 1) / b; }

// The forward's pixel block: at most pixel_block(), at least 64 pixels, a multiple of 16, an
// image's pixels cut into equal blocks that share out evenly over the threads this call runs on
// (balanced_task_units, parallel_threads_here).
int64_t forward_pixel_block(const ConvGeometry& g, int64_t batch) {
  return balanced_task_units(g.pixels(), batch, pixel_block(g, kForwardBlockFloats), 64, 16,
                             parallel_threads_here());
}

}  // namespace

// y (+)= conv(x, w) (+ bias) over raw NCHW arrays with geometry g: one task per (image, pixel
// block), y[n][:, block] = w [Co, K] * col [K, block] (beta = 1 when accumulating); with an
// epilogue, each task applies it to its block.
void im2col_convolve(const ConvGeometry& g, int64_t batch, int64_t out_channels, const float* px,
                     const float* pw, const float* pb, float* py, bool accumulate,
                     const Epilogue* epilogue) {
  const int64_t rows = g.rows();
  const int64_t pixels = g.pixels();
  const int64_t block = forward_pixel_block(g, batch);
  const int64_t blocks = ceil_div(pixels, block);
  const bool pointwise = is_pointwise(g);
  const float beta = accumulate ? 1.0f : 0.0f;
  parallel_for(batch * blocks, 1, [&](int64_t begin, int64_t end) {
    for (int64_t t = begin; t < end; ++t) {
      const int64_t n = t / blocks;
      const int64_t p0 = (t % blocks) * block;
      const int64_t count = std::min(block, pixels - p0);
      const float* image = px + n * g.channels * g.height * g.width;
      float* out = py + n * out_channels * pixels + p0;
      if (pointwise) {
        sgemm(false, false, out_channels, count, rows, 1.0f, pw, rows, image + p0, pixels, beta,
              out, pixels);
      } else {
        float* col = thread_workspace(static_cast<size_t>(rows * count));
        im2col_block(g, image, 0, g.channels, p0, count, col);
        sgemm(false, false, out_channels, count, rows, 1.0f, pw, rows, col, count, beta, out,
              pixels);
      }
      if (pb) {
        for (int64_t co = 0; co < out_channels; ++co) {
          float* row = out + co * pixels;
          for (int64_t j = 0; j < count; ++j) row[j] += pb[co];
        }
      }
      if (epilogue)
        for (int64_t co = 0; co < out_channels; ++co) epilogue->apply(py, n, co, p0, count);
    }
  });
}

// y (+)= conv(x, w) (+ bias): Winograd where it applies, im2col + SGEMM otherwise.
void CpuBackend::convolve_any(const ConvGeometry& g, int64_t batch, int64_t out_channels,
                              const float* x, const float* w, const float* bias, float* y,
                              bool accumulate) {
  if (winograd_applicable(g, out_channels)) {
    Scratch transformed = scratch(winograd_weight_floats(g, out_channels));
    winograd_convolve(g, batch, out_channels, x, w, bias, y, accumulate, transformed.data());
  } else {
    im2col_convolve(g, batch, out_channels, x, w, bias, y, accumulate, nullptr);
  }
}

void CpuBackend::conv2d(const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y,
                        const Conv2dParams& p) {
  convolve_any(geometry(x, w, y, p), x.shape().n(), w.shape().n(), ptr(x), ptr(w),
               bias ? ptr(*bias) : nullptr, ptr(y), false);
}

void CpuBackend::conv2d_backward(const Tensor& x, const Tensor& w, const Tensor& dy,
                                 const Tensor* dx, const Tensor* dw, const Tensor* dbias,
                                 const Conv2dParams& p, bool accumulate) {
  const ConvGeometry g = geometry(x, w, dy, p);
  const int64_t batch = x.shape().n();
  const int64_t out_channels = w.shape().n();
  const int64_t rows = g.rows();
  const int64_t taps = g.kernel * g.kernel;
  const int64_t pixels = g.pixels();
  const int64_t image_size = g.channels * g.height * g.width;
  const float* px = ptr(x);
  const float* pw = ptr(w);
  const float* pdy = ptr(dy);
  const bool pointwise = is_pointwise(g);

  if (dbias) {
    float* pdb = ptr(*dbias);
    parallel_for(out_channels, 1, [&](int64_t begin, int64_t end) {
      for (int64_t co = begin; co < end; ++co) {
        double total = 0.0;
        for (int64_t n = 0; n < batch; ++n) {
          const float* row = pdy + (n * out_channels + co) * pixels;
          float partial = 0.0f;
          for (int64_t j = 0; j < pixels; ++j) partial += row[j];
          total += partial;
        }
        store(pdb[co], static_cast<float>(total), accumulate);
      }
    });
  }

  // The flipped convolution's GEMM has M = Ci rows: worth it only with enough input channels
  // (the 7x7 3->64 layer's dx went from 52 to 127 ms that way).
  const bool dx_as_convolution =
      p.stride == 1 && 2 * g.pad == g.kernel - 1 && !pointwise && g.channels >= 32;
  if (dx && dx_as_convolution) {
    // A stride-1 "same" convolution's input gradient is itself a same convolution of dy with
    // the weights flipped in space and transposed: dx[ci] = sum_co dy[co] (*) w[co, ci] rotated
    // by 180 degrees. That runs on the forward path (K = Co * k * k) instead of a K = Co GEMM
    // plus col2im: 3x3 128->128 at 64x64, batch 20, 157 -> 118 ms.
    Scratch flipped = scratch(static_cast<size_t>(out_channels * rows));
    float* pf = flipped.data();
    for (int64_t co = 0; co < out_channels; ++co)
      for (int64_t ci = 0; ci < g.channels; ++ci)
        for (int64_t t = 0; t < taps; ++t)
          pf[(ci * out_channels + co) * taps + (taps - 1 - t)] =
              pw[(co * g.channels + ci) * taps + t];
    ConvGeometry back = g;
    back.channels = out_channels;
    back.height = g.out_height;
    back.width = g.out_width;
    back.out_height = g.height;
    back.out_width = g.width;
    convolve_any(back, batch, g.channels, pdy, pf, nullptr, ptr(*dx), accumulate);
  } else if (dx) {
    // Input channel c only receives from im2col rows of channel c, so tasks over (image,
    // channel group) write disjoint parts of dx. Enough groups to keep every thread busy.
    float* pdx = ptr(*dx);
    const int64_t groups =
        std::min<int64_t>(g.channels, ceil_div(2 * parallel_thread_count(), batch));
    const int64_t group_size = ceil_div(g.channels, groups);
    const int64_t block = pixel_block(g, kForwardBlockFloats);
    parallel_for(batch * groups, 1, [&](int64_t begin, int64_t end) {
      for (int64_t t = begin; t < end; ++t) {
        const int64_t n = t / groups;
        const int64_t c0 = (t % groups) * group_size;
        const int64_t c1 = std::min(g.channels, c0 + group_size);
        if (c0 >= c1) continue;
        float* image_grad = pdx + n * image_size;
        const float* grad_out = pdy + n * out_channels * pixels;
        const float* w_rows = pw + c0 * taps;  // columns of w [Co, K] for channels [c0, c1)
        const int64_t group_rows = (c1 - c0) * taps;
        if (pointwise) {
          // dx[c0:c1, :] = w[:, c0:c1]^T * dy
          sgemm(true, false, group_rows, pixels, out_channels, 1.0f, w_rows, rows, grad_out,
                pixels, accumulate ? 1.0f : 0.0f, image_grad + c0 * pixels, pixels);
          continue;
        }
        if (!accumulate)
          std::fill(image_grad + c0 * g.height * g.width, image_grad + c1 * g.height * g.width,
                    0.0f);
        for (int64_t p0 = 0; p0 < pixels; p0 += block) {
          const int64_t count = std::min(block, pixels - p0);
          float* col = thread_workspace(static_cast<size_t>(group_rows * count));
          sgemm(true, false, group_rows, count, out_channels, 1.0f, w_rows, rows, grad_out + p0,
                pixels, 0.0f, col, count);
          col2im_block_add(g, col, c0, c1, p0, count, image_grad);
        }
      }
    });
  }

  if (dw && winograd_applicable(g, out_channels)) {
    Scratch partials = scratch(winograd_weight_gradient_floats(g, out_channels));
    winograd_weight_gradient(g, batch, out_channels, px, pdy, ptr(*dw), accumulate,
                             partials.data());
  } else if (dw) {
    // The (image, pixel block) tasks are split into one contiguous range per lane (as many
    // lanes as threads); each lane sums dy * col^T over its range into its own partial [Co, K],
    // and the partials are added up in lane order at the end. The split does not depend on
    // which thread runs which lane, so the result is the same bits every run (exact resume).
    const int64_t block = pixel_block(g, kWeightGradBlockFloats);
    const int64_t blocks = ceil_div(pixels, block);
    const int64_t weights = out_channels * rows;
    const int64_t tasks = batch * blocks;
    const int threads = static_cast<int>(std::min<int64_t>(parallel_thread_count(), tasks));
    Scratch partials = scratch(static_cast<size_t>(threads * weights));
    std::vector<char> used(static_cast<size_t>(threads), 0);
    parallel_for(threads, 1, [&](int64_t lane_begin, int64_t lane_end) {
      for (int64_t slot = lane_begin; slot < lane_end; ++slot) {
      float* partial = partials.data() + slot * weights;
      for (int64_t t = tasks * slot / threads; t < tasks * (slot + 1) / threads; ++t) {
        const int64_t n = t / blocks;
        const int64_t p0 = (t % blocks) * block;
        const int64_t count = std::min(block, pixels - p0);
        const float* image = px + n * image_size;
        const float* grad_out = pdy + n * out_channels * pixels + p0;
        const float beta = used[slot] ? 1.0f : 0.0f;
        if (pointwise) {
          sgemm(false, true, out_channels, rows, count, 1.0f, grad_out, pixels, image + p0,
                pixels, beta, partial, rows);
        } else {
          float* col = thread_workspace(static_cast<size_t>(rows * count));
          im2col_block(g, image, 0, g.channels, p0, count, col);
          sgemm(false, true, out_channels, rows, count, 1.0f, grad_out, pixels, col, count, beta,
                partial, rows);
        }
        used[slot] = 1;
      }
      }
    });
    float* pdw = ptr(*dw);
    const float* base = partials.data();
    parallel_for(weights, kElementwiseGrain, [&](int64_t begin, int64_t end) {
      for (int64_t i = begin; i < end; ++i) {
        float total = 0.0f;
        for (int s = 0; s < threads; ++s)
          if (used[s]) total += base[s * weights + i];
        store(pdw[i], total, accumulate);
      }
    });
  }
}

}  // namespace facetool::cpu
