// Winograd F(4x4, 3x3) convolution on the cpu: 3x3 stride-1 "same" layers in a quarter of the GEMM work.
#pragma once

#include <cstddef>
#include <cstdint>

#include "backends/cpu/cpu_epilogue.h"
#include "backends/cpu/cpu_im2col.h"

namespace facetool::cpu {

// Whether winograd_convolve handles this geometry: 3x3 kernel, stride 1, padding 1, output the
// size of the input, and enough channels on both sides for the transforms to pay off.
bool winograd_applicable(const ConvGeometry& g, int64_t out_channels);

// Floats winograd_convolve needs in `transformed_weights`: 36 * out_channels * channels.
size_t winograd_weight_floats(const ConvGeometry& g, int64_t out_channels);

// y (+)= conv(x, w) (+ bias) over raw NCHW arrays, like the im2col path, computed as
// y_tile = A^T [ (G w G^T) .* (B^T x_tile B) ] A over 4x4 output tiles: the element-wise product
// summed over input channels is 36 GEMMs [Co, Ci] x [Ci, tiles]. `transformed_weights` is
// scratch of winograd_weight_floats() floats. With `epilogue`, each task applies it to the
// output pixels it wrote (bias nullptr and accumulate false then).
void winograd_convolve(const ConvGeometry& g, int64_t batch, int64_t out_channels,
                       const float* x, const float* w, const float* bias, float* y,
                       bool accumulate, float* transformed_weights,
                       const Epilogue* epilogue = nullptr);

// transformed_weights (winograd_weight_floats() floats) = G w G^T for every (co, ci): what
// winograd_convolve computes at every call, for a caller that keeps it between calls.
void winograd_transform_weights(const ConvGeometry& g, int64_t out_channels, const float* w,
                                float* transformed_weights);

// winograd_convolve on weights transformed before (winograd_transform_weights).
void winograd_convolve_transformed(const ConvGeometry& g, int64_t batch, int64_t out_channels,
                                   const float* x, const float* transformed_weights,
                                   const float* bias, float* y, bool accumulate,
                                   const Epilogue* epilogue = nullptr);

// Floats winograd_weight_gradient needs in `partials`: one set of 36 [Co, Ci] sums per thread.
size_t winograd_weight_gradient_floats(const ConvGeometry& g, int64_t out_channels);

// dw (+)= the weight gradient of that convolution given its input x and output gradient dy,
// as dw = G^T [ sum over tiles of (A dy_tile A^T) .* (B^T x_tile B) ] G: 36 GEMMs
// [Co, tiles] x [tiles, Ci] summed into per-thread partials (scratch of
// winograd_weight_gradient_floats() floats).
void winograd_weight_gradient(const ConvGeometry& g, int64_t batch, int64_t out_channels,
                              const float* x, const float* dy, float* dw, bool accumulate,
                              float* partials);

}  // namespace facetool::cpu
