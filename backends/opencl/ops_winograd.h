// The opencl backend's Winograd F(4x4, 3x3) convolution: forward, input and weight gradients.
#pragma once

#include <cstdint>

#include "core/tensor/tensor.h"

namespace facetool::opencl {

class OpenclBackend;

// Whether the Winograd path handles a convolution: 3x3, stride 1, padding 1, output the size of
// the input, and >= 32 channels on both sides.
bool winograd_applicable(int64_t kernel, int64_t stride, int64_t pad, int64_t in_channels,
                         int64_t out_channels, bool same_size);

// One convolution seen by the Winograd path: `in_channels` -> `out_channels` on height x width.
struct WinogradProblem {
  int64_t batch, in_channels, out_channels, height, width;
};

// y (+)= conv(x, w) (+ bias). flipped: w is stored [in_channels][out_channels][3][3] and used
// rotated by 180 degrees, which makes this the input gradient of the convolution w belongs to.
void winograd_convolve(OpenclBackend& be, const WinogradProblem& p, const Tensor& x,
                       const Tensor& w, bool flipped, const Tensor* bias, const Tensor& y,
                       bool accumulate);

// dw (+)= the weight gradient of conv(x, w) given dy (dw [out][in][3][3]).
void winograd_weight_gradient(OpenclBackend& be, const WinogradProblem& p, const Tensor& x,
                              const Tensor& dy, const Tensor& dw, bool accumulate);

}  // namespace facetool::opencl
