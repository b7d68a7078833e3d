// The cpu backend's forward convolution algorithms on raw arrays, for the plain and fused paths.
#pragma once

#include <cstdint>

#include "backends/cpu/cpu_epilogue.h"
#include "backends/cpu/cpu_im2col.h"

namespace facetool::cpu {

// y (+)= conv(x, w) (+ bias) by im2col + SGEMM over (image, pixel block) tasks; with
// `epilogue` (bias nullptr, accumulate false), each task applies it to the block it computed.
void im2col_convolve(const ConvGeometry& g, int64_t batch, int64_t out_channels, const float* x,
                     const float* w, const float* bias, float* y, bool accumulate,
                     const Epilogue* epilogue);

// Whether direct_convolve runs this shape: stride 1, padding under the kernel, the output the
// size the padding gives.
bool direct_conv_applicable(const ConvGeometry& g);

// y = conv(x, w), then `epilogue` when given, summed tap by tap from a zero-padded copy of x
// (no im2col matrix: for few output channels, whose matrix would be written to be read once).
// Output channels go four at a time; a shape direct_conv_applicable refuses returns false.
bool direct_convolve(const ConvGeometry& g, int64_t batch, int64_t out_channels, const float* x,
                     const float* w, float* y, const Epilogue* epilogue);

// y = conv(x, w) by oneDNN's convolution primitive (its own algorithm and blocked layouts,
// threads through OpenMP), then `epilogue` when given. False when oneDNN has no primitive for it.
bool dnnl_convolve(const ConvGeometry& g, int64_t batch, int64_t out_channels, const float* x,
                   const float* w, float* y, const Epilogue* epilogue);

}  // namespace facetool::cpu
