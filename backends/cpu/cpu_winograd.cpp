// Winograd F(4x4, 3x3): weight, input-tile and output-tile transforms around 36 SGEMMs.
#include "backends/cpu/cpu_winograd.h"

#include <algorithm>
#include <vector>

#include "backends/cpu/cpu_backend_impl.h"
#include "backends/cpu/cpu_task_split.h"
#include "backends/cpu/cpu_workspace.h"
#include "backends/cpu/gemm.h"
#include "core/util/parallel_for.h"
#include "core/util/vector_clones.h"

namespace facetool::cpu {
namespace {

constexpr int64_t kTile = 4;     // output tile edge
constexpr int64_t kPatch = 6;    // input patch edge: kTile + 3 - 1
constexpr int64_t kPoints = 36;  // transformed values per tile: kPatch^2
// Tiles per task: the task's transformed input (36 x Ci x tiles floats) stays near L2.
constexpr int64_t kTilesPerTask = 128;

// The transforms of Lavin and Gray for interpolation points 0, 1, -1, 2, -2 and infinity,
// each applied along one axis to vectors of n values (one per tile): the k-th input vector
// starts at in + k * in_stride, the i-th output vector at out + i * out_stride.

// out = B^T in: 6 -> 6.
FACETOOL_VECTOR_CLONES
void input_transform(const float* __restrict in, int64_t in_stride, float* __restrict out,
                     int64_t out_stride, int64_t n) {
  const float *d0 = in, *d1 = in + in_stride, *d2 = in + 2 * in_stride,
              *d3 = in + 3 * in_stride, *d4 = in + 4 * in_stride, *d5 = in + 5 * in_stride;
  float *o0 = out, *o1 = out + out_stride, *o2 = out + 2 * out_stride,
        *o3 = out + 3 * out_stride, *o4 = out + 4 * out_stride, *o5 = out + 5 * out_stride;
  FACETOOL_NO_ALIAS_LOOP
  for (int64_t j = 0; j < n; ++j) {
    o0[j] = 4.0f * d0[j] - 5.0f * d2[j] + d4[j];
    o1[j] = -4.0f * (d1[j] + d2[j]) + d3[j] + d4[j];
    o2[j] = 4.0f * (d1[j] - d2[j]) - d3[j] + d4[j];
    o3[j] = 2.0f * (d3[j] - d1[j]) - d2[j] + d4[j];
    o4[j] = 2.0f * (d1[j] - d3[j]) - d2[j] + d4[j];
    o5[j] = 4.0f * d1[j] - 5.0f * d3[j] + d5[j];
  }
}

// out = A^T in: 6 -> 4.
FACETOOL_VECTOR_CLONES
void output_transform(const float* __restrict in, int64_t in_stride, float* __restrict out,
                      int64_t out_stride, int64_t n) {
  const float *m0 = in, *m1 = in + in_stride, *m2 = in + 2 * in_stride,
              *m3 = in + 3 * in_stride, *m4 = in + 4 * in_stride, *m5 = in + 5 * in_stride;
  float *o0 = out, *o1 = out + out_stride, *o2 = out + 2 * out_stride,
        *o3 = out + 3 * out_stride;
  FACETOOL_NO_ALIAS_LOOP
  for (int64_t j = 0; j < n; ++j) {
    const float sum12 = m1[j] + m2[j], diff12 = m1[j] - m2[j];
    const float sum34 = m3[j] + m4[j], diff34 = m3[j] - m4[j];
    o0[j] = m0[j] + sum12 + sum34;
    o1[j] = diff12 + 2.0f * diff34;
    o2[j] = sum12 + 4.0f * sum34;
    o3[j] = diff12 + 8.0f * diff34 + m5[j];
  }
}

// out = G in: 3 -> 6 (in double: it builds the coefficient table below).
void weight_transform(const double in[3], double out[6]) {
  out[0] = in[0] / 4.0;
  out[1] = -(in[0] + in[1] + in[2]) / 6.0;
  out[2] = -(in[0] - in[1] + in[2]) / 6.0;
  out[3] = in[0] / 24.0 + in[1] / 12.0 + in[2] / 6.0;
  out[4] = in[0] / 24.0 - in[1] / 12.0 + in[2] / 6.0;
  out[5] = in[2];
}

// out = A in: 4 -> 6, the adjoint of output_transform (for the weight gradient's dy tiles).
FACETOOL_VECTOR_CLONES
void output_transform_adjoint(const float* __restrict in, int64_t in_stride,
                              float* __restrict out, int64_t out_stride, int64_t n) {
  const float *d0 = in, *d1 = in + in_stride, *d2 = in + 2 * in_stride,
              *d3 = in + 3 * in_stride;
  float *o0 = out, *o1 = out + out_stride, *o2 = out + 2 * out_stride,
        *o3 = out + 3 * out_stride, *o4 = out + 4 * out_stride, *o5 = out + 5 * out_stride;
  FACETOOL_NO_ALIAS_LOOP
  for (int64_t j = 0; j < n; ++j) {
    const float even = d0[j] + 4.0f * d2[j], odd = 2.0f * d1[j] + 8.0f * d3[j];
    o0[j] = d0[j];
    o1[j] = d0[j] + d1[j] + d2[j] + d3[j];
    o2[j] = d0[j] - d1[j] + d2[j] - d3[j];
    o3[j] = even + odd;
    o4[j] = even - odd;
    o5[j] = d3[j];
  }
}

// out = G^T in: 6 -> 3, the adjoint of weight_transform.
void weight_transform_adjoint(const double in[6], double out[3]) {
  out[0] = in[0] / 4.0 - (in[1] + in[2]) / 6.0 + (in[3] + in[4]) / 24.0;
  out[1] = (in[2] - in[1]) / 6.0 + (in[3] - in[4]) / 12.0;
  out[2] = (in[3] + in[4] - in[1] - in[2]) / 6.0 + in[5];
}

// (G w G^T)[i][s] = sum over taps (ky, kx) of G[i][ky] G[s][kx] w[ky][kx]: the 36 x 9
// coefficients, computed in double from weight_transform applied to unit vectors.
struct WeightTransformCoefficients {
  float c[kPoints][9];
  WeightTransformCoefficients() {
    double g[6][3];  // G[i][k]
    for (int k = 0; k < 3; ++k) {
      double unit[3] = {0, 0, 0}, column[6];
      unit[k] = 1.0;
      weight_transform(unit, column);
      for (int i = 0; i < 6; ++i) g[i][k] = column[i];
    }
    for (int i = 0; i < 6; ++i)
      for (int s = 0; s < 6; ++s)
        for (int ky = 0; ky < 3; ++ky)
          for (int kx = 0; kx < 3; ++kx)
            c[i * kPatch + s][ky * 3 + kx] = static_cast<float>(g[i][ky] * g[s][kx]);
  }
};

// u[xi][co][ci] = (G w[co, ci] G^T)[xi]: 36 matrices [Co, Ci]. Per output channel, the 9 taps
// are first laid out as rows over ci, so every transformed row is a vectorised sum of them.
FACETOOL_VECTOR_CLONES
void transform_output_channel(const float* w, int64_t co, int64_t out_channels,
                              int64_t channels, float* taps, float* u) {
  static const WeightTransformCoefficients coefficients;
  for (int64_t ci = 0; ci < channels; ++ci)
    for (int t = 0; t < 9; ++t) taps[t * channels + ci] = w[(co * channels + ci) * 9 + t];
  for (int64_t xi = 0; xi < kPoints; ++xi) {
    float* __restrict row = u + (xi * out_channels + co) * channels;
    std::fill(row, row + channels, 0.0f);
    for (int t = 0; t < 9; ++t) {
      const float c = coefficients.c[xi][t];
      if (c == 0.0f) continue;
      const float* __restrict tap = taps + t * channels;
      for (int64_t ci = 0; ci < channels; ++ci) row[ci] += c * tap[ci];
    }
  }
}

// Where one task's tiles are: image n, tiles [first, first + count) in row-major tile order.
struct TileRange {
  int64_t n, first, count;
};

// Calls visit(j0, ty, tx0, tx1) for each run of tiles in one tile row: tiles j0, j0 + 1, ...
// of the range are (ty, tx0), (ty, tx0 + 1), ... (ty, tx1 - 1).
template <typename Visit>
void for_each_tile_row(const TileRange& r, int64_t tiles_x, Visit visit) {
  int64_t tile = r.first;
  const int64_t end = r.first + r.count;
  while (tile < end) {
    const int64_t ty = tile / tiles_x;
    const int64_t tx0 = tile % tiles_x;
    const int64_t tx1 = std::min(tiles_x, tx0 + (end - tile));
    visit(tile - r.first, ty, tx0, tx1);
    tile += tx1 - tx0;
  }
}

// Input rows split into their four column phases, so that patch column px of consecutive tiles
// (input columns 4 tx + px - 1) is a contiguous run: row r (input row first_row + r), phase p,
// entry k + 1 holds x[row][4 k + p] for k in [-1, tiles_x], 0 outside the image.
struct PhaseRows {
  const float* data;
  int64_t first_row, phase_stride, row_stride;
  // The run of patch column px for tiles tx, tx + 1, ... of patch row `row`.
  const float* column(int64_t row, int64_t px, int64_t tx) const {
    const int64_t u = px - 1;  // column offset from 4 tx: -1 .. 4
    const int64_t phase = (u + kTile) % kTile, shift = u < 0 ? -1 : u / kTile;
    return data + (row - first_row) * row_stride + phase * phase_stride + tx + shift + 1;
  }
};

FACETOOL_VECTOR_CLONES
void split_phases(const ConvGeometry& g, const float* plane, int64_t first_row, int64_t rows,
                  int64_t phase_stride, float* out) {
  for (int64_t r = 0; r < rows; ++r) {
    const int64_t iy = first_row + r;
    float* row_out = out + r * kTile * phase_stride;
    if (iy < 0 || iy >= g.height) {
      std::fill(row_out, row_out + kTile * phase_stride, 0.0f);
      continue;
    }
    const float* in = plane + iy * g.width;
    // The groups of four columns wholly inside the row go to the four phases in one pass (a
    // 4-way de-interleave the compiler vectorises: one pass per phase, each a strided read of
    // the whole row, was 11 % of a training step); then each phase's rest.
    float* d0 = row_out;
    float* d1 = row_out + phase_stride;
    float* d2 = row_out + 2 * phase_stride;
    float* d3 = row_out + 3 * phase_stride;
    const int64_t groups = std::min<int64_t>(g.width / kTile, phase_stride - 1);
    for (int64_t k = 0; k < groups; ++k) {
      d0[k + 1] = in[kTile * k];
      d1[k + 1] = in[kTile * k + 1];
      d2[k + 1] = in[kTile * k + 2];
      d3[k + 1] = in[kTile * k + 3];
    }
    for (int64_t p = 0; p < kTile; ++p) {
      float* dst = row_out + p * phase_stride;  // dst[kk] = in[4 (kk - 1) + p]
      // Entries kk in [1, hi) lie inside the row: 0 <= 4 (kk - 1) + p < width (kk = 0 is
      // column p - 4 < 0); [1, groups] are written above.
      const int64_t hi = std::clamp<int64_t>((g.width - p + kTile - 1) / kTile + 1, 1, phase_stride);
      dst[0] = 0.0f;
      for (int64_t kk = groups + 1; kk < hi; ++kk) dst[kk] = in[kTile * (kk - 1) + p];
      std::fill(dst + hi, dst + phase_stride, 0.0f);  // hi >= groups + 1
    }
  }
}

// One output row of a run of tiles: out[4 tx + b] (+)= row_b[tx] + bias for tx in [tx0, tx1),
// clipped at `width`. Whole tiles store their 4 values next to each other, which the compiler
// turns into vector interleaves rather than 4 stride-4 passes.
FACETOOL_VECTOR_CLONES
void store_tile_row(const float* const rows[kTile], int64_t tx0, int64_t tx1, int64_t width,
                    float bias, bool accumulate, float* out) {
  const int64_t whole = std::clamp<int64_t>(width / kTile, tx0, tx1);
  const float *r0 = rows[0], *r1 = rows[1], *r2 = rows[2], *r3 = rows[3];
  if (accumulate) {
    for (int64_t tx = tx0; tx < whole; ++tx) {
      out[4 * tx] += r0[tx] + bias;
      out[4 * tx + 1] += r1[tx] + bias;
      out[4 * tx + 2] += r2[tx] + bias;
      out[4 * tx + 3] += r3[tx] + bias;
    }
  } else {
    for (int64_t tx = tx0; tx < whole; ++tx) {
      out[4 * tx] = r0[tx] + bias;
      out[4 * tx + 1] = r1[tx] + bias;
      out[4 * tx + 2] = r2[tx] + bias;
      out[4 * tx + 3] = r3[tx] + bias;
    }
  }
  for (int64_t tx = whole; tx < tx1; ++tx)  // the tile cut by the image's right edge
    for (int64_t b = 0; b < kTile && kTile * tx + b < width; ++b)
      store(out[kTile * tx + b], rows[b][tx] + bias, accumulate);
}

// plane (+)= tile values tiles[(a * 4 + b) * stride + j] + bias, clipped to the image.
void scatter_tiles(const ConvGeometry& g, int64_t tiles_x, const float* tiles, int64_t stride,
                   const TileRange& r, float bias, float* plane, bool accumulate) {
  for_each_tile_row(r, tiles_x, [&](int64_t j0, int64_t ty, int64_t tx0, int64_t tx1) {
    for (int64_t a = 0; a < kTile; ++a) {
      const int64_t oy = ty * kTile + a;
      if (oy >= g.out_height) break;
      const float* rows[kTile];  // rows[b][tx]: value (a, b) of tile tx
      for (int64_t b = 0; b < kTile; ++b) rows[b] = tiles + (a * kTile + b) * stride + j0 - tx0;
      store_tile_row(rows, tx0, tx1, g.out_width, bias, accumulate, plane + oy * g.out_width);
    }
  });
}

// One output row read into a run of tiles: rows[b][tx] = in[4 tx + b] for tx in [tx0, tx1), 0 at
// or past `width` (the adjoint of store_tile_row; whole tiles load 4 neighbours at a time).
FACETOOL_VECTOR_CLONES
void load_tile_row(const float* in, int64_t tx0, int64_t tx1, int64_t width,
                   float* const rows[kTile]) {
  const int64_t whole = std::clamp<int64_t>(width / kTile, tx0, tx1);
  float *r0 = rows[0], *r1 = rows[1], *r2 = rows[2], *r3 = rows[3];
  for (int64_t tx = tx0; tx < whole; ++tx) {
    r0[tx] = in[4 * tx];
    r1[tx] = in[4 * tx + 1];
    r2[tx] = in[4 * tx + 2];
    r3[tx] = in[4 * tx + 3];
  }
  for (int64_t tx = whole; tx < tx1; ++tx)
    for (int64_t b = 0; b < kTile; ++b)
      rows[b][tx] = kTile * tx + b < width ? in[kTile * tx + b] : 0.0f;
}

// tiles[(a * 4 + b) * stride + j] = plane at output pixel (4 ty + a, 4 tx + b) of tile j, or 0
// past the image's edge: the adjoint of scatter_tiles.
void gather_tiles(const ConvGeometry& g, int64_t tiles_x, const float* plane, const TileRange& r,
                  int64_t stride, float* tiles) {
  for_each_tile_row(r, tiles_x, [&](int64_t j0, int64_t ty, int64_t tx0, int64_t tx1) {
    for (int64_t a = 0; a < kTile; ++a) {
      const int64_t oy = ty * kTile + a;
      float* rows[kTile];  // rows[b][tx]: value (a, b) of tile tx
      for (int64_t b = 0; b < kTile; ++b) rows[b] = tiles + (a * kTile + b) * stride + j0 - tx0;
      if (oy < g.out_height) {
        load_tile_row(plane + oy * g.out_width, tx0, tx1, g.out_width, rows);
      } else {
        for (int64_t b = 0; b < kTile; ++b) std::fill(rows[b] + tx0, rows[b] + tx1, 0.0f);
      }
    }
  });
}

// Per-thread buffers of one task: transformed inputs, products or dy tiles, the 4x4 tiles of one
// channel, and a staging area for transforms done one axis at a time.
struct TaskBuffers {
  float* v;      // [36][Ci][T]: B^T patch B of every input channel
  float* m;      // [36][Co][T]: GEMM products (forward) or A dy A^T (weight gradient)
  float* tiles;  // [16][T]: one channel's output (forward) or dy (weight gradient) tiles
  float* half;   // [36][T]: after one axis of a transform
};

TaskBuffers task_buffers(int64_t channels, int64_t out_channels) {
  const int64_t T = kTilesPerTask;
  constexpr int64_t kTileValues = kTile * kTile;
  TaskBuffers b;
  b.v = thread_workspace(
      static_cast<size_t>(T * (kPoints * (channels + out_channels + 1) + kTileValues)));
  b.m = b.v + kPoints * channels * T;
  b.tiles = b.m + kPoints * out_channels * T;
  b.half = b.tiles + kTileValues * T;
  return b;
}

// The tiles of a convolution's output: 4x4 each, row-major within an image, cut into tasks of
// kTilesPerTask tiles that never span two images.
struct Tiling {
  int64_t tiles_x, tiles, per_task, tasks_per_image;
  // per_task <= kTilesPerTask tiles per task (fewer give small batches more tasks than threads).
  explicit Tiling(const ConvGeometry& g, int64_t per_task_tiles = kTilesPerTask)
      : tiles_x((g.out_width + kTile - 1) / kTile),
        tiles(tiles_x * ((g.out_height + kTile - 1) / kTile)),
        per_task(std::clamp<int64_t>(per_task_tiles, 1, kTilesPerTask)),
        tasks_per_image((tiles + per_task - 1) / per_task) {}
  TileRange task(int64_t t) const {
    TileRange r;
    r.n = t / tasks_per_image;
    r.first = (t % tasks_per_image) * per_task;
    r.count = std::min(per_task, tiles - r.first);
    return r;
  }
};

// Tiles per forward task: at most kTilesPerTask, at least 16, an image's tiles cut into equal
// tasks that share out evenly over the threads this call runs on (balanced_task_units,
// parallel_threads_here).
int64_t forward_tiles_per_task(const ConvGeometry& g, int64_t batch) {
  return balanced_task_units(Tiling(g).tiles, batch, kTilesPerTask, 16, 1, parallel_threads_here());
}

// b.v[xi][c][j] = (B^T patch B)[xi] of tile j for every input channel c of image r.n.
void transform_input_tiles(const ConvGeometry& g, const Tiling& t, const float* x,
                           const TileRange& r, const TaskBuffers& b) {
  const int64_t T = kTilesPerTask;
  const int64_t channels = g.channels;
  // The input rows under the task's tile rows, phase-split once per channel.
  const int64_t first_ty = r.first / t.tiles_x, last_ty = (r.first + r.count - 1) / t.tiles_x;
  PhaseRows phases;
  phases.first_row = first_ty * kTile - 1;
  phases.phase_stride = t.tiles_x + 2;
  phases.row_stride = kTile * phases.phase_stride;
  const int64_t rows = (last_ty - first_ty) * kTile + kPatch;
  thread_local std::vector<float> phase_storage;
  phase_storage.resize(static_cast<size_t>(rows * phases.row_stride));
  phases.data = phase_storage.data();
  for (int64_t c = 0; c < channels; ++c) {
    split_phases(g, x + (r.n * channels + c) * g.height * g.width, phases.first_row, rows,
                 phases.phase_stride, phase_storage.data());
    // Along the patch's rows: half[i][px] = (B^T d) for each patch column px.
    for_each_tile_row(r, t.tiles_x, [&](int64_t j0, int64_t ty, int64_t tx0, int64_t tx1) {
      for (int64_t px = 0; px < kPatch; ++px)
        input_transform(phases.column(ty * kTile - 1, px, tx0), phases.row_stride,
                        b.half + px * T + j0, kPatch * T, tx1 - tx0);
    });
    for (int64_t i = 0; i < kPatch; ++i)  // along its columns: v[i][s'] = (B^T d B)
      input_transform(b.half + i * kPatch * T, T, b.v + (i * kPatch * channels + c) * T,
                      channels * T, r.count);
  }
}

}  // namespace

bool winograd_applicable(const ConvGeometry& g, int64_t out_channels) {
  return g.kernel == 3 && g.stride == 1 && g.pad == 1 && g.out_height == g.height &&
         g.out_width == g.width && g.channels >= 16 && out_channels >= 16;
}

size_t winograd_weight_floats(const ConvGeometry& g, int64_t out_channels) {
  return static_cast<size_t>(kPoints * out_channels * g.channels);
}

void winograd_transform_weights(const ConvGeometry& g, int64_t out_channels, const float* w,
                                float* transformed_weights) {
  parallel_for(out_channels, 1, [&](int64_t begin, int64_t end) {
    thread_local std::vector<float> taps;
    taps.resize(static_cast<size_t>(9 * g.channels));
    for (int64_t co = begin; co < end; ++co)
      transform_output_channel(w, co, out_channels, g.channels, taps.data(), transformed_weights);
  });
}

void winograd_convolve(const ConvGeometry& g, int64_t batch, int64_t out_channels,
                       const float* x, const float* w, const float* bias, float* y,
                       bool accumulate, float* transformed_weights, const Epilogue* epilogue) {
  winograd_transform_weights(g, out_channels, w, transformed_weights);
  winograd_convolve_transformed(g, batch, out_channels, x, transformed_weights, bias, y,
                                accumulate, epilogue);
}

void winograd_convolve_transformed(const ConvGeometry& g, int64_t batch, int64_t out_channels,
                                   const float* x, const float* u, const float* bias, float* y,
                                   bool accumulate, const Epilogue* epilogue) {
  const int64_t channels = g.channels;
  const int64_t out_plane = g.out_height * g.out_width;
  const int64_t T = kTilesPerTask;  // stride between the vectors of one tile value
  const Tiling tiling(g, forward_tiles_per_task(g, batch));

  parallel_for(batch * tiling.tasks_per_image, 1, [&](int64_t begin, int64_t end) {
    const TaskBuffers b = task_buffers(channels, out_channels);
    for (int64_t task = begin; task < end; ++task) {
      const TileRange r = tiling.task(task);
      transform_input_tiles(g, tiling, x, r, b);
      // m[xi] = u[xi] [Co, Ci] x v[xi] [Ci, tiles]
      for (int64_t xi = 0; xi < kPoints; ++xi)
        sgemm(false, false, out_channels, r.count, channels, 1.0f,
              u + xi * out_channels * channels, channels, b.v + xi * channels * T, T, 0.0f,
              b.m + xi * out_channels * T, T);
      // y tile = A^T m A for every output channel.
      for (int64_t co = 0; co < out_channels; ++co) {
        for (int64_t s = 0; s < kPatch; ++s)  // half[a][s] = (A^T m)
          output_transform(b.m + (s * out_channels + co) * T, kPatch * out_channels * T,
                           b.half + s * T, kPatch * T, r.count);
        float* tile_values = b.tiles;
        for (int64_t a = 0; a < kTile; ++a)  // tile_values[a][b] = (A^T m A)
          output_transform(b.half + a * kPatch * T, T, tile_values + a * kTile * T, T, r.count);
        scatter_tiles(g, tiling.tiles_x, tile_values, T, r, bias ? bias[co] : 0.0f,
                      y + (r.n * out_channels + co) * out_plane, accumulate);
        if (epilogue) {  // the pixels this task just wrote, row by row
          for_each_tile_row(r, tiling.tiles_x, [&](int64_t, int64_t ty, int64_t tx0, int64_t tx1) {
            const int64_t x0 = tx0 * kTile, x1 = std::min(g.out_width, tx1 * kTile);
            for (int64_t oy = ty * kTile; oy < std::min(g.out_height, (ty + 1) * kTile); ++oy)
              epilogue->apply(y, r.n, co, oy * g.out_width + x0, x1 - x0);
          });
        }
      }
    }
  });
}

size_t winograd_weight_gradient_floats(const ConvGeometry& g, int64_t out_channels) {
  return static_cast<size_t>(parallel_thread_count()) * winograd_weight_floats(g, out_channels);
}

void winograd_weight_gradient(const ConvGeometry& g, int64_t batch, int64_t out_channels,
                              const float* x, const float* dy, float* dw, bool accumulate,
                              float* partials) {
  const int64_t channels = g.channels;
  const int64_t out_plane = g.out_height * g.out_width;
  const int64_t T = kTilesPerTask;
  const int64_t weights = kPoints * out_channels * channels;
  const Tiling tiling(g);
  // One contiguous range of tasks per lane (as many lanes as threads), each lane summing into
  // its own partial, added up in lane order: the same bits whichever thread runs which lane.
  const int64_t tasks = batch * tiling.tasks_per_image;
  const int64_t lanes = std::min<int64_t>(parallel_thread_count(), tasks);
  std::vector<char> used(static_cast<size_t>(lanes), 0);

  // partial[xi] [Co, Ci] += (A dy A^T)[xi] [Co, tiles] x (B^T x B)[xi]^T [tiles, Ci]
  parallel_for(lanes, 1, [&](int64_t lane_begin, int64_t lane_end) {
    for (int64_t slot = lane_begin; slot < lane_end; ++slot) {
    float* partial = partials + slot * weights;
    const TaskBuffers b = task_buffers(channels, out_channels);
    for (int64_t task = tasks * slot / lanes; task < tasks * (slot + 1) / lanes; ++task) {
      const TileRange r = tiling.task(task);
      transform_input_tiles(g, tiling, x, r, b);
      for (int64_t co = 0; co < out_channels; ++co) {
        float* tile_values = b.tiles;
        gather_tiles(g, tiling.tiles_x, dy + (r.n * out_channels + co) * out_plane, r, T,
                     tile_values);
        for (int64_t col = 0; col < kTile; ++col)  // along the tile's rows: half[i][col]
          output_transform_adjoint(tile_values + col * T, kTile * T, b.half + col * T,
                                   kTile * T, r.count);
        for (int64_t i = 0; i < kPatch; ++i)  // along its columns: m[i][s] = (A dy A^T)
          output_transform_adjoint(b.half + i * kTile * T, T,
                                   b.m + (i * kPatch * out_channels + co) * T,
                                   out_channels * T, r.count);
      }
      const float beta = used[slot] ? 1.0f : 0.0f;
      for (int64_t xi = 0; xi < kPoints; ++xi)
        sgemm(false, true, out_channels, channels, r.count, 1.0f, b.m + xi * out_channels * T,
              T, b.v + xi * channels * T, T, beta, partial + xi * out_channels * channels,
              channels);
      used[slot] = 1;
    }
    }
  });

  // dw[co, ci] = G^T (sum of the partials) G
  const int64_t pairs = out_channels * channels;
  parallel_for(pairs, 64, [&](int64_t begin, int64_t end) {
    for (int64_t pair = begin; pair < end; ++pair) {
      double summed[6][6] = {};
      for (size_t slot = 0; slot < used.size(); ++slot) {
        if (!used[slot]) continue;
        const float* partial = partials + static_cast<int64_t>(slot) * weights + pair;
        for (int64_t xi = 0; xi < kPoints; ++xi) summed[xi / kPatch][xi % kPatch] += partial[xi * pairs];
      }
      double rows[3][6];  // (G^T S)[ky][s]
      for (int64_t s = 0; s < kPatch; ++s) {
        double column[6], reduced[3];
        for (int64_t i = 0; i < kPatch; ++i) column[i] = summed[i][s];
        weight_transform_adjoint(column, reduced);
        for (int ky = 0; ky < 3; ++ky) rows[ky][s] = reduced[ky];
      }
      float* out = dw + pair * 9;
      for (int ky = 0; ky < 3; ++ky) {
        double reduced[3];
        weight_transform_adjoint(rows[ky], reduced);
        for (int kx = 0; kx < 3; ++kx) store(out[ky * 3 + kx], static_cast<float>(reduced[kx]), accumulate);
      }
    }
  });
}

}  // namespace facetool::cpu
