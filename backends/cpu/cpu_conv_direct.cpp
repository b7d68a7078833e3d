// Direct stride-1 convolution for few output channels: taps summed from a zero-padded input copy.
#include <algorithm>
#include <vector>

#include "backends/cpu/cpu_conv.h"
#include "core/util/parallel_for.h"
#include "core/util/vector_clones.h"

namespace facetool::cpu {
namespace {

// Outputs summed together in registers: two AVX-512 vectors (four AVX2) per output channel.
// (Measured on a Zen 4 machine, 2026-12-07: blocks of 16 outputs for 8 channels, or 64 for 1,
// were no faster; stride 2 through phase planes was no faster than im2col.)
constexpr int64_t kBlock = 32;
// Output channels summed together (a group's weights are interleaved per tap).
constexpr int64_t kGroup = 4;
// Flattened outputs per task: about this many, a whole number of padded rows.
constexpr int64_t kTaskOutputs = 2048;

// With stride 1, output (oy, ox) reads padded input (oy + ky, ox + kx): on the padded image's
// flattened rows (width wp), output q = oy * wp + ox reads q + ky * wp + kx, one offset per tap
// for every output. Columns ox >= out_width of that grid are computed and dropped.

// Sixteen floats (one AVX-512 vector, two AVX2 ones); Vec16u is the same read from or written to
// any float's address. The sums are named values, not arrays: an array of vectors is memory that
// the compiler may assume 64-byte aligned, which AddressSanitizer's frames for locals are not.
typedef float Vec16 __attribute__((vector_size(64)));
typedef float Vec16u __attribute__((vector_size(64), aligned(4)));

Vec16 load(const float* at) { return *reinterpret_cast<const Vec16u*>(at); }
void store(float* at, Vec16 v) { *reinterpret_cast<Vec16u*>(at) = v; }

// sums[g * kBlock + j] = sum over taps t of weights[t * G + g] * padded[offsets[t] + q0 + j], for
// G = 1 or 4 output channels and the kBlock = 32 outputs from q0 (written with vector types:
// GCC left the plain loops scalar).
FACETOOL_VECTOR_CLONES
void block_sums_1(const float* padded, const int64_t* offsets, const float* weights, int64_t taps, int64_t q0,
                  float* sums) {
  Vec16 a0 = {}, a1 = {};
  for (int64_t t = 0; t < taps; ++t) {
    const float* in = padded + offsets[t] + q0;
    const Vec16 x0 = load(in), x1 = load(in + 16);
    a0 += weights[t] * x0;
    a1 += weights[t] * x1;
  }
  store(sums, a0);
  store(sums + 16, a1);
}

FACETOOL_VECTOR_CLONES
void block_sums_4(const float* padded, const int64_t* offsets, const float* weights, int64_t taps, int64_t q0,
                  float* sums) {
  static_assert(kGroup == 4 && kBlock == 32, "block_sums_4 sums 4 channels x 32 outputs");
  Vec16 a0 = {}, a1 = {}, b0 = {}, b1 = {}, c0 = {}, c1 = {}, d0 = {}, d1 = {};
  for (int64_t t = 0; t < taps; ++t) {
    const float* in = padded + offsets[t] + q0;
    const float* w = weights + t * 4;
    const Vec16 x0 = load(in), x1 = load(in + 16);
    a0 += w[0] * x0;
    a1 += w[0] * x1;
    b0 += w[1] * x0;
    b1 += w[1] * x1;
    c0 += w[2] * x0;
    c1 += w[2] * x1;
    d0 += w[3] * x0;
    d1 += w[3] * x1;
  }
  store(sums, a0);
  store(sums + 16, a1);
  store(sums + 32, b0);
  store(sums + 48, b1);
  store(sums + 64, c0);
  store(sums + 80, c1);
  store(sums + 96, d0);
  store(sums + 112, d1);
}

}  // namespace

bool direct_conv_applicable(const ConvGeometry& g) {
  return g.stride == 1 && g.pad >= 0 && g.pad < g.kernel && g.out_height == g.height + 2 * g.pad - g.kernel + 1 &&
         g.out_width == g.width + 2 * g.pad - g.kernel + 1 && g.out_height > 0 && g.out_width > 0;
}

bool direct_convolve(const ConvGeometry& g, int64_t batch, int64_t out_channels, const float* x, const float* w,
                     float* y, const Epilogue* epilogue) {
  if (!direct_conv_applicable(g)) return false;
  const int64_t k = g.kernel, wp = g.width + 2 * g.pad;
  // One row more than the padding needs: the dropped columns of the last output row read past it.
  const int64_t hp = g.height + 2 * g.pad + 1;
  const int64_t channel_floats = hp * wp;
  const int64_t image_floats = g.channels * channel_floats;
  const int64_t taps = g.channels * k * k;
  // Blocks start at multiples of kBlock and may run past the last output: kBlock floats of slack.
  std::vector<float> padded(static_cast<size_t>(batch * image_floats + kBlock), 0.0f);
  parallel_for(batch * g.channels, 1, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const float* from = x + i * g.height * g.width;
      float* to = padded.data() + i * channel_floats + g.pad * wp + g.pad;
      for (int64_t iy = 0; iy < g.height; ++iy) std::copy(from + iy * g.width, from + (iy + 1) * g.width, to + iy * wp);
    }
  });
  std::vector<int64_t> offsets(static_cast<size_t>(taps));
  for (int64_t c = 0; c < g.channels; ++c)
    for (int64_t ky = 0; ky < k; ++ky)
      for (int64_t kx = 0; kx < k; ++kx) offsets[static_cast<size_t>((c * k + ky) * k + kx)] = c * channel_floats + ky * wp + kx;
  // Each group's weights, tap-major: [taps][G] (a partial last group padded with zero weights).
  const int64_t groups = (out_channels + kGroup - 1) / kGroup;
  std::vector<float> grouped(static_cast<size_t>(groups * taps * kGroup), 0.0f);
  for (int64_t co = 0; co < out_channels; ++co)
    for (int64_t t = 0; t < taps; ++t)
      grouped[static_cast<size_t>(((co / kGroup) * taps + t) * kGroup + co % kGroup)] = w[co * taps + t];

  const int64_t rows_per_task = std::max<int64_t>(1, kTaskOutputs / wp);
  const int64_t tasks_per_image = (g.out_height + rows_per_task - 1) / rows_per_task;
  parallel_for(batch * groups * tasks_per_image, 1, [&](int64_t begin, int64_t end) {
    std::vector<float> sums(static_cast<size_t>(kGroup * kBlock));
    for (int64_t task = begin; task < end; ++task) {
      const int64_t n = task / (groups * tasks_per_image), group = task / tasks_per_image % groups;
      const int64_t oy0 = (task % tasks_per_image) * rows_per_task;
      const int64_t oy1 = std::min(g.out_height, oy0 + rows_per_task);
      const int64_t g0 = group * kGroup, count = std::min(kGroup, out_channels - g0);
      const float* image = padded.data() + n * image_floats;
      const float* weights = grouped.data() + group * taps * kGroup;
      // Flattened outputs [oy0 * wp, oy1 * wp), one block at a time; the valid columns go to y.
      for (int64_t q0 = oy0 * wp; q0 < oy1 * wp; q0 += kBlock) {
        if (count == 1)
          block_sums_1(image, offsets.data(), w + g0 * taps, taps, q0, sums.data());  // w[g0] is [taps]
        else
          block_sums_4(image, offsets.data(), weights, taps, q0, sums.data());
        for (int64_t j = 0; j < kBlock; ++j) {
          const int64_t q = q0 + j, oy = q / wp, ox = q % wp;
          if (oy >= oy1) break;
          if (ox >= g.out_width) continue;
          for (int64_t c = 0; c < count; ++c)
            y[((n * out_channels + g0 + c) * g.out_height + oy) * g.out_width + ox] = sums[static_cast<size_t>(c * kBlock + j)];
        }
      }
      if (epilogue)
        for (int64_t c = 0; c < count; ++c)
          epilogue->apply(y, n, g0 + c, oy0 * g.out_width, (oy1 - oy0) * g.out_width);
    }
  });
  return true;
}

}  // namespace facetool::cpu
