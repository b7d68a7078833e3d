// The paper's network (section 4.2): shared encoder, albedo and shape branches, light estimator.
#pragma once

#include <array>

#include "core/plugin/network_plugin.h"
#include "plugins/paper_network/layers.h"

namespace facetool::paper_network {

// 'Albedo Residual' / 'Shape Residual': 5 ResBLK - BN - LReLU.
class ResidualStack {
 public:
  ResidualStack() = default;
  ResidualStack(Backend& be, ParameterSet& set, const std::string& name, int64_t channels);
  ag::Variable operator()(const ag::Variable& x, bool training) const;
  Tensor infer(const Tensor& x) const;  // eval without autograd, fused

 private:
  std::array<ResidualBlock, 5> blocks_;
  BatchNorm bn_;
};

// 'Albedo Conv.' / 'Shape Conv.': Up - C(k3) - C/2(k3) - C*out(k1).
class Decoder {
 public:
  Decoder() = default;
  Decoder(Backend& be, ParameterSet& set, const std::string& name, int64_t channels, int64_t out);
  ag::Variable operator()(const ag::Variable& x, bool training) const;
  // Eval without autograd, fused; `last` is the output layer's activation.
  Tensor infer(const Tensor& x, ConvEpilogue::Activation last) const;

 private:
  ConvBnRelu conv1_, conv2_;
  Conv out_;
};

class PaperNetwork final : public NetworkPlugin {
 public:
  void build(Backend& backend, const NetworkConfig& config) override;
  const NetworkConfig& config() const override { return config_; }
  std::vector<std::pair<std::string, ag::Variable>> parameters() const override;
  std::vector<std::pair<std::string, Tensor>> buffers() const override;
  void init_random(uint64_t seed) override;
  NetworkOutputs forward(const ag::Variable& images, bool training) override;
  double forward_flops_per_image() const override;

 private:
  // Eval mode on the fused ops (core/ops/fused_ops.cpp): batch norms folded into the
  // convolutions, activations and residual additions in their epilogues, no autograd graph.
  NetworkOutputs forward_fused(const Tensor& images) const;
  NetworkOutputs forward_fused_chunk(const Tensor& images) const;  // one chunk of images

  NetworkConfig config_;
  int prior_channels_ = 0;  // input_prior_channels(config_.input_prior)
  bool built_ = false;
  ParameterSet set_;
  // 'Conv.': C/2(k7) - C(k3) - C*(k3, stride 2, no BN)
  ConvBnRelu stem1_, stem2_;
  Conv stem_down_;
  ResidualStack albedo_residual_, shape_residual_;
  Decoder albedo_decoder_, shape_decoder_;
  // 'Illumination Estimator': concat - 1x1 C - BN - LReLU - average pool - FC 27
  ConvBnRelu light_conv_;
  Linear light_fc_;
};

}  // namespace facetool::paper_network
