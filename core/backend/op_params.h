// Parameter structs of the ops whose behaviour depends on more than their tensors.
#pragma once

#include <cstdint>

namespace facetool {

// 2-D convolution, square kernel of odd size, zero padding. Output size
// (in + 2*pad - kernel) / stride + 1. `pad < 0` means "same" padding: kernel / 2.
struct Conv2dParams {
  int stride = 1;
  int pad = -1;
  int effective_pad(int64_t kernel) const { return pad < 0 ? static_cast<int>(kernel / 2) : pad; }
};

// Batch normalisation with PyTorch semantics: training mode normalises with the batch mean
// and biased variance and updates running_mean/running_var with `momentum` (the running
// variance takes the unbiased batch variance); eval mode uses the running statistics.
struct BatchNormParams {
  bool training = true;
  float momentum = 0.1f;
  float eps = 1e-5f;
};

// Adam with PyTorch's update rule (bias-corrected moments; eps added after the square root;
// weight_decay adds weight_decay * param to the gradient, the L2 form of torch.optim.Adam).
struct AdamParams {
  float lr = 1e-3f;
  float beta1 = 0.9f;
  float beta2 = 0.999f;
  float eps = 1e-8f;
  float weight_decay = 0.0f;
  int64_t step = 1;  // 1 for the first update
};

}  // namespace facetool
