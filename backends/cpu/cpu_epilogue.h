// The cpu side of ConvEpilogue: applied to runs of output pixels right after they are computed.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/backend/backend.h"

namespace facetool::cpu {

// ConvEpilogue on raw host arrays of an output [N, Co, plane].
struct Epilogue {
  const float* scale = nullptr;
  const float* shift = nullptr;
  const float* residual = nullptr;
  ConvEpilogue::Activation activation = ConvEpilogue::Activation::None;
  float slope = 0.0f;
  float* y2 = nullptr;
  const float* post_scale = nullptr;
  const float* post_shift = nullptr;
  float post_slope = 0.0f;
  int64_t out_channels = 0;
  int64_t plane = 0;

  // y[n, co, offset + j] for j < count: from the raw convolution sum to the epilogue's values
  // (and y2 written alongside).
  void apply(float* y, int64_t n, int64_t co, int64_t offset, int64_t count) const {
    const int64_t base = (n * out_channels + co) * plane + offset;
    float* __restrict out = y + base;
    const float s = scale ? scale[co] : 1.0f;
    const float t = shift ? shift[co] : 0.0f;
    if (residual) {
      const float* __restrict r = residual + base;
      for (int64_t j = 0; j < count; ++j) out[j] = s * out[j] + t + r[j];
    } else {
      for (int64_t j = 0; j < count; ++j) out[j] = s * out[j] + t;
    }
    if (activation == ConvEpilogue::Activation::LeakyRelu) {
      const float a = slope;
      for (int64_t j = 0; j < count; ++j) out[j] = out[j] > 0.0f ? out[j] : a * out[j];
    } else if (activation == ConvEpilogue::Activation::Sigmoid) {
      for (int64_t j = 0; j < count; ++j) out[j] = 1.0f / (1.0f + std::exp(-out[j]));
    }
    if (y2) {
      float* __restrict second = y2 + base;
      const float ps = post_scale[co], pt = post_shift[co], a = post_slope;
      for (int64_t j = 0; j < count; ++j) {
        const float v = ps * out[j] + pt;
        second[j] = v > 0.0f ? v : a * v;
      }
    }
  }
};

}  // namespace facetool::cpu
