// Building blocks of the paper's network: convolution and batch-norm layers with named parameters.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/autograd/functions.h"
#include "core/backend/backend.h"

namespace facetool::paper_network {

// Collects every parameter and buffer under its full dotted name as layers are created.
struct ParameterSet {
  std::vector<std::pair<std::string, ag::Variable>> parameters;
  std::vector<std::pair<std::string, Tensor>> buffers;
  // Kaiming fan-in and gain of each weight, by parameter index, for init_random.
  struct InitRule {
    size_t index;
    int64_t fan_in;
    float gain;  // 0: fill with `fill` instead
    float fill;
  };
  std::vector<InitRule> init;
};

// Convolution with bias; `gain` is the Kaiming gain of the activation that follows.
class Conv {
 public:
  Conv() = default;
  Conv(Backend& be, ParameterSet& set, const std::string& name, int64_t in, int64_t out,
       int64_t kernel, int stride, float gain);
  ag::Variable operator()(const ag::Variable& x) const;
  // Eval without autograd: conv(x) then `e`, whose shift defaults to this layer's bias.
  Tensor infer(const Tensor& x, ConvEpilogue e) const;
  const Tensor& bias() const { return bias_.value(); }

 private:
  ag::Variable weight_, bias_;
  Conv2dParams params_;
};

class BatchNorm {
 public:
  BatchNorm() = default;
  BatchNorm(Backend& be, ParameterSet& set, const std::string& name, int64_t channels);
  ag::Variable operator()(const ag::Variable& x, bool training) const;
  // leaky_relu(batch_norm(x)) with the paper's slope, fused (ag::batch_norm_leaky_relu).
  ag::Variable activated(const ag::Variable& x, bool training) const;
  // Eval mode as one per-channel affine map applied to the output of a layer with `bias`
  // (nullptr: none): y = scale * x + shift.
  void fold(const Tensor* bias, Tensor& scale, Tensor& shift) const;
  // Eval without autograd: leaky_relu(batch_norm(x)) in one pass.
  Tensor infer_leaky_relu(const Tensor& x) const;

 private:
  ag::Variable gamma_, beta_;
  Tensor running_mean_, running_var_;
};

class Linear {
 public:
  Linear() = default;
  Linear(Backend& be, ParameterSet& set, const std::string& name, int64_t in, int64_t out);
  ag::Variable operator()(const ag::Variable& x) const;

 private:
  ag::Variable weight_, bias_;
};

constexpr float kLeakySlope = 0.2f;  // the paper's LReLU slope
// Kaiming gain for a leaky ReLU with the paper's slope: sqrt(2 / (1 + slope^2)).
float leaky_relu_gain();

// conv -> batch norm -> LReLU, the paper's "CN(kS)".
class ConvBnRelu {
 public:
  ConvBnRelu() = default;
  ConvBnRelu(Backend& be, ParameterSet& set, const std::string& name, int64_t in, int64_t out,
             int64_t kernel);
  ag::Variable operator()(const ag::Variable& x, bool training) const;
  // Eval without autograd: the batch norm folded into the convolution, leaky ReLU fused.
  Tensor infer(const Tensor& x) const;

 private:
  Conv conv_;
  BatchNorm bn_;
};

// The paper's ResBLK: BN - LReLU - C - BN - LReLU - C, plus the identity.
class ResidualBlock {
 public:
  ResidualBlock() = default;
  ResidualBlock(Backend& be, ParameterSet& set, const std::string& name, int64_t channels);
  ag::Variable operator()(const ag::Variable& x, bool training) const;
  // Eval without autograd, given x and activated = leaky_relu(bn1(x)) (computed by the layer
  // before): returns x + block(x) and sets next_activated = leaky_relu(next(x + block(x))),
  // the next layer's batch norm computed in the last convolution's epilogue.
  Tensor infer(const Tensor& x, const Tensor& activated, const BatchNorm& next,
               Tensor& next_activated) const;
  const BatchNorm& first_norm() const { return bn1_; }

 private:
  BatchNorm bn1_;
  Conv conv1_;
  BatchNorm bn2_;
  Conv conv2_;
};

}  // namespace facetool::paper_network
