// Building blocks of the paper's network: parameter creation and forward passes.
#include "plugins/paper_network/layers.h"

#include <cmath>

#include "core/ops/ops.h"

namespace facetool::paper_network {

namespace {

ag::Variable add_parameter(Backend& be, ParameterSet& set, const std::string& name,
                           const Shape& shape, int64_t fan_in, float gain, float fill) {
  ag::Variable v(Tensor::empty(be, shape), true);
  set.init.push_back({set.parameters.size(), fan_in, gain, fill});
  set.parameters.emplace_back(name, v);
  return v;
}

}  // namespace

float leaky_relu_gain() { return std::sqrt(2.0f / (1.0f + kLeakySlope * kLeakySlope)); }

Conv::Conv(Backend& be, ParameterSet& set, const std::string& name, int64_t in, int64_t out,
           int64_t kernel, int stride, float gain) {
  weight_ = add_parameter(be, set, name + ".weight", Shape{out, in, kernel, kernel},
                          in * kernel * kernel, gain, 0.0f);
  bias_ = add_parameter(be, set, name + ".bias", Shape{out}, 0, 0.0f, 0.0f);
  params_.stride = stride;
}

ag::Variable Conv::operator()(const ag::Variable& x) const {
  return ag::conv2d(x, weight_, bias_, params_);
}

Tensor Conv::infer(const Tensor& x, ConvEpilogue e) const {
  if (!e.scale && !e.shift) e.shift = &bias_.value();
  return ops::conv2d_fused(x, weight_.value(), params_, e);
}

BatchNorm::BatchNorm(Backend& be, ParameterSet& set, const std::string& name, int64_t channels) {
  gamma_ = add_parameter(be, set, name + ".weight", Shape{channels}, 0, 0.0f, 1.0f);
  beta_ = add_parameter(be, set, name + ".bias", Shape{channels}, 0, 0.0f, 0.0f);
  running_mean_ = Tensor::zeros(be, Shape{channels});
  running_var_ = Tensor::full(be, Shape{channels}, 1.0f);
  set.buffers.emplace_back(name + ".running_mean", running_mean_);
  set.buffers.emplace_back(name + ".running_var", running_var_);
}

ag::Variable BatchNorm::operator()(const ag::Variable& x, bool training) const {
  BatchNormParams p;
  p.training = training;
  return ag::batch_norm(x, gamma_, beta_, running_mean_, running_var_, p);
}

ag::Variable BatchNorm::activated(const ag::Variable& x, bool training) const {
  BatchNormParams p;
  p.training = training;
  return ag::batch_norm_leaky_relu(x, gamma_, beta_, running_mean_, running_var_, p, kLeakySlope);
}

void BatchNorm::fold(const Tensor* bias, Tensor& scale, Tensor& shift) const {
  ops::fold_batch_norm(gamma_.value(), beta_.value(), running_mean_, running_var_,
                       BatchNormParams{}.eps, bias, scale, shift);
}

Tensor BatchNorm::infer_leaky_relu(const Tensor& x) const {
  Tensor scale, shift;
  fold(nullptr, scale, shift);
  return ops::channel_affine_leaky_relu(x, scale, shift, kLeakySlope);
}

Linear::Linear(Backend& be, ParameterSet& set, const std::string& name, int64_t in, int64_t out) {
  weight_ = add_parameter(be, set, name + ".weight", Shape{out, in}, in, 1.0f, 0.0f);
  bias_ = add_parameter(be, set, name + ".bias", Shape{out}, 0, 0.0f, 0.0f);
}

ag::Variable Linear::operator()(const ag::Variable& x) const {
  return ag::linear(x, weight_, bias_);
}

ConvBnRelu::ConvBnRelu(Backend& be, ParameterSet& set, const std::string& name, int64_t in,
                       int64_t out, int64_t kernel)
    : conv_(be, set, name + ".conv", in, out, kernel, 1, leaky_relu_gain()),
      bn_(be, set, name + ".bn", out) {}

ag::Variable ConvBnRelu::operator()(const ag::Variable& x, bool training) const {
  return bn_.activated(conv_(x), training);
}

Tensor ConvBnRelu::infer(const Tensor& x) const {
  Tensor scale, shift;
  bn_.fold(&conv_.bias(), scale, shift);
  ConvEpilogue e;
  e.scale = &scale;
  e.shift = &shift;
  e.activation = ConvEpilogue::Activation::LeakyRelu;
  e.slope = kLeakySlope;
  return conv_.infer(x, e);
}

ResidualBlock::ResidualBlock(Backend& be, ParameterSet& set, const std::string& name,
                             int64_t channels)
    : bn1_(be, set, name + ".bn1", channels),
      conv1_(be, set, name + ".conv1", channels, channels, 3, 1, leaky_relu_gain()),
      bn2_(be, set, name + ".bn2", channels),
      conv2_(be, set, name + ".conv2", channels, channels, 3, 1, leaky_relu_gain()) {}

ag::Variable ResidualBlock::operator()(const ag::Variable& x, bool training) const {
  ag::Variable h = conv1_(bn1_.activated(x, training));
  h = conv2_(bn2_.activated(h, training));
  return ag::add(x, h);
}

}  // namespace facetool::paper_network

namespace facetool::paper_network {

Tensor ResidualBlock::infer(const Tensor& x, const Tensor& activated, const BatchNorm& next,
                            Tensor& next_activated) const {
  // conv1 -> bn2 -> LReLU: bn2 folded into conv1.
  Tensor scale, shift;
  bn2_.fold(&conv1_.bias(), scale, shift);
  ConvEpilogue first;
  first.scale = &scale;
  first.shift = &shift;
  first.activation = ConvEpilogue::Activation::LeakyRelu;
  first.slope = kLeakySlope;
  const Tensor h = conv1_.infer(activated, first);
  // conv2 + bias + x, and the next batch norm + LReLU of that sum as the second output.
  Tensor post_scale, post_shift;
  next.fold(nullptr, post_scale, post_shift);
  next_activated = Tensor::empty(x.backend(), x.shape());
  ConvEpilogue second;
  second.residual = &x;
  second.y2 = &next_activated;
  second.post_scale = &post_scale;
  second.post_shift = &post_shift;
  second.post_slope = kLeakySlope;
  return conv2_.infer(h, second);
}

}  // namespace facetool::paper_network
