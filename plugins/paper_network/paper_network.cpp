// The paper's network: layer wiring, deterministic initialisation and the forward pass.
#include "plugins/paper_network/paper_network.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/ops/ops.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"

namespace facetool::paper_network {

ResidualStack::ResidualStack(Backend& be, ParameterSet& set, const std::string& name,
                             int64_t channels) {
  for (size_t i = 0; i < blocks_.size(); ++i)
    blocks_[i] = ResidualBlock(be, set, name + ".block" + std::to_string(i), channels);
  bn_ = BatchNorm(be, set, name + ".bn", channels);
}

ag::Variable ResidualStack::operator()(const ag::Variable& x, bool training) const {
  ag::Variable h = x;
  for (const ResidualBlock& block : blocks_) h = block(h, training);
  return bn_.activated(h, training);
}

Tensor ResidualStack::infer(const Tensor& x) const {
  Tensor h = x;
  Tensor activated = blocks_[0].first_norm().infer_leaky_relu(x);
  for (size_t i = 0; i < blocks_.size(); ++i) {
    const BatchNorm& next = i + 1 < blocks_.size() ? blocks_[i + 1].first_norm() : bn_;
    Tensor next_activated;
    h = blocks_[i].infer(h, activated, next, next_activated);
    activated = next_activated;
  }
  return activated;  // leaky_relu(bn(h)): the stack's output
}

Decoder::Decoder(Backend& be, ParameterSet& set, const std::string& name, int64_t channels,
                 int64_t out)
    : conv1_(be, set, name + ".layer1", channels, channels, 3),
      conv2_(be, set, name + ".layer2", channels, channels / 2, 3),
      out_(be, set, name + ".out", channels / 2, out, 1, 1, 1.0f) {}

ag::Variable Decoder::operator()(const ag::Variable& x, bool training) const {
  return out_(conv2_(conv1_(ag::upsample_bilinear2x(x), training), training));
}

Tensor Decoder::infer(const Tensor& x, ConvEpilogue::Activation last) const {
  const Tensor h = conv2_.infer(conv1_.infer(ops::upsample_bilinear2x(x)));
  ConvEpilogue e;
  e.activation = last;
  return out_.infer(h, e);
}

void PaperNetwork::build(Backend& be, const NetworkConfig& config) {
  check(!built_, "paper_network: build() called twice");
  check(config.width >= 2 && config.width % 2 == 0, "paper_network: width must be an even ",
        "number >= 2, got ", config.width);
  check(config.input_size >= 2 && config.input_size % 2 == 0, "paper_network: input size must ",
        "be an even number >= 2, got ", config.input_size);
  prior_channels_ = input_prior_channels(config.input_prior);
  config_ = config;
  const int64_t c = config.width;
  stem1_ = ConvBnRelu(be, set_, "encoder.layer1", 3 + prior_channels_, c / 2, 7);
  stem2_ = ConvBnRelu(be, set_, "encoder.layer2", c / 2, c, 3);
  stem_down_ = Conv(be, set_, "encoder.down", c, c, 3, 2, leaky_relu_gain());
  albedo_residual_ = ResidualStack(be, set_, "albedo_residual", c);
  shape_residual_ = ResidualStack(be, set_, "shape_residual", c);
  albedo_decoder_ = Decoder(be, set_, "albedo_decoder", c, 3);
  shape_decoder_ = Decoder(be, set_, "shape_decoder", c, 12);
  light_conv_ = ConvBnRelu(be, set_, "light.layer1", 3 * c, c, 1);
  light_fc_ = Linear(be, set_, "light.fc", c, 27);
  built_ = true;
}

std::vector<std::pair<std::string, ag::Variable>> PaperNetwork::parameters() const {
  return set_.parameters;
}

std::vector<std::pair<std::string, Tensor>> PaperNetwork::buffers() const { return set_.buffers; }

void PaperNetwork::init_random(uint64_t seed) {
  check(built_, "paper_network: init_random() before build()");
  // Box-Muller on a fixed generator, so the same seed gives the same weights on every platform
  // (std::normal_distribution's algorithm is implementation-defined).
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
  for (const ParameterSet::InitRule& rule : set_.init) {
    const Tensor& t = set_.parameters[rule.index].second.value();
    std::vector<float> values(static_cast<size_t>(t.numel()), rule.fill);
    if (rule.gain > 0.0f) {
      const double std_dev = rule.gain / std::sqrt(static_cast<double>(rule.fan_in));
      for (size_t i = 0; i < values.size(); i += 2) {
        const double r = std::sqrt(-2.0 * std::log(uniform()));
        const double angle = 2.0 * kPi * uniform();
        values[i] = static_cast<float>(std_dev * r * std::cos(angle));
        if (i + 1 < values.size()) values[i + 1] = static_cast<float>(std_dev * r * std::sin(angle));
      }
    }
    t.copy_from_host(values);
  }
  for (auto& [name, buffer] : set_.buffers) {
    const bool is_var = name.size() >= 11 && name.compare(name.size() - 11, 11, "running_var") == 0;
    buffer.copy_from_host(std::vector<float>(static_cast<size_t>(buffer.numel()), is_var ? 1.0f : 0.0f));
  }
}

double PaperNetwork::forward_flops_per_image() const {
  const double c = config_.width, s = config_.input_size, h = s / 2;
  auto conv = [](double in, double out, double k, double res) { return 2 * in * out * k * k * res * res; };
  double flops = conv(3 + prior_channels_, c / 2, 7, s) + conv(c / 2, c, 3, s) + conv(c, c, 3, h);
  flops += 2 * 10 * conv(c, c, 3, h);                                           // residual stacks
  flops += 2 * (conv(c, c, 3, s) + conv(c, c / 2, 3, s)) + conv(c / 2, 3, 1, s) +  // decoders
           conv(c / 2, 12, 1, s);
  flops += conv(3 * c, c, 1, h) + 2 * c * 27;                                   // light
  return flops;
}

namespace {

// `s` with its first dimension replaced (the outputs are rank 4, or rank 2 for the light).
Shape with_batch(const Shape& s, int64_t n) {
  return s.rank() == 4 ? Shape{n, s[1], s[2], s[3]} : Shape{n, s[1]};
}

// Images [n0, n0 + count) of x [N, ...] as a new tensor (x viewed as one image of N * C channels).
Tensor slice_batch(const Tensor& x, int64_t n0, int64_t count) {
  const Shape& s = x.shape();
  const int64_t per_image = s.numel() / s[0];
  const Tensor flat = x.reshaped(Shape{1, s[0] * per_image, 1, 1});
  return ops::slice_channels(flat, n0 * per_image, count * per_image)
      .reshaped(with_batch(s, count));
}

// The parts' images one after the other (the inverse of slice_batch).
Tensor concat_batch(const std::vector<Tensor>& parts) {
  std::vector<Tensor> flat;
  int64_t images = 0;
  for (const Tensor& p : parts) {
    flat.push_back(p.reshaped(Shape{1, p.numel(), 1, 1}));
    images += p.shape()[0];
  }
  return ops::concat_channels(flat).reshaped(with_batch(parts.front().shape(), images));
}

}  // namespace

NetworkOutputs PaperNetwork::forward_fused(const Tensor& images) const {
  // Large batches can run a few images at a time, so that the activations of a chunk stay in
  // cache from one layer to the next; the backend says how many (the cpu backend: as many as
  // fit 4 MiB of the widest activation unless this machine measured otherwise, `bench network
  // --save`; docs/performance.md).
  const int64_t widest = static_cast<int64_t>(config_.width) * config_.input_size *
                         config_.input_size * static_cast<int64_t>(sizeof(float));
  const int64_t batch = images.shape().n();
  const int64_t chunk = images.backend().fused_batch_chunk(widest, batch);
  if (batch <= chunk) return forward_fused_chunk(images);
  std::vector<Tensor> albedo, normal, visibility, light;
  for (int64_t n0 = 0; n0 < batch; n0 += chunk) {
    NetworkOutputs part = forward_fused_chunk(slice_batch(images, n0, std::min(chunk, batch - n0)));
    albedo.push_back(part.albedo.value());
    normal.push_back(part.normal.value());
    visibility.push_back(part.visibility.value());
    light.push_back(part.light.value());
  }
  NetworkOutputs out;
  out.albedo = ag::Variable(concat_batch(albedo));
  out.normal = ag::Variable(concat_batch(normal));
  out.visibility = ag::Variable(concat_batch(visibility));
  out.light = ag::Variable(concat_batch(light));
  return out;
}

NetworkOutputs PaperNetwork::forward_fused_chunk(const Tensor& images) const {
  const Tensor h = stem2_.infer(stem1_.infer(images));
  ConvEpilogue down;
  down.activation = ConvEpilogue::Activation::LeakyRelu;
  down.slope = kLeakySlope;
  const Tensor features = stem_down_.infer(h, down);
  // The albedo and shape halves depend on `features` alone: the backend may run them at once.
  Tensor albedo_features, shape_features, albedo, shape;
  images.backend().run_branches(
      images.shape().n(),
      {[&] {
         albedo_features = albedo_residual_.infer(features);
         albedo = albedo_decoder_.infer(albedo_features, ConvEpilogue::Activation::Sigmoid);
       },
       [&] {
         shape_features = shape_residual_.infer(features);
         shape = shape_decoder_.infer(shape_features, ConvEpilogue::Activation::None);
       }});

  NetworkOutputs out;
  out.albedo = ag::Variable(albedo);
  Tensor normal = ops::slice_channels(shape, 0, 3);
  if (prior_channels_ > 0) normal = ops::add(normal, ops::slice_channels(images, 3, 3));
  out.normal = ag::Variable(ops::l2_normalize(normal));
  out.visibility = ag::Variable(ops::slice_channels(shape, 3, 9));
  const Tensor joint = ops::concat_channels({features, albedo_features, shape_features});
  out.light = light_fc_(ag::Variable(ops::global_avg_pool(light_conv_.infer(joint))));
  return out;
}

NetworkOutputs PaperNetwork::forward(const ag::Variable& images, bool training) {
  check(built_, "paper_network: forward() before build()");
  const Shape& s = images.shape();
  check(s.rank() == 4 && s.c() == 3 + prior_channels_ && s.h() == config_.input_size &&
            s.w() == config_.input_size,
        "paper_network: expected images of shape [N, ", 3 + prior_channels_, ", ", config_.input_size,
        ", ", config_.input_size, "]", prior_channels_ ? " (RGB and the input prior)" : "", ", got ", s.str());
  // Evaluation that nothing will differentiate runs fused where the backend has fused ops;
  // FACETOOL_PLAIN_OPS=1 (or ops::set_fused_paths_enabled(false)) keeps the plain path below.
  if (!training && !images.requires_grad() && ops::fused_paths_enabled() &&
      ops::backend_has_fused_ops(images.backend()))
    return forward_fused(images.value());
  ag::Variable h = stem2_(stem1_(images, training), training);
  ag::Variable features = ag::leaky_relu(stem_down_(h), kLeakySlope);
  ag::Variable albedo_features = albedo_residual_(features, training);
  ag::Variable shape_features = shape_residual_(features, training);

  NetworkOutputs out;
  out.albedo = ag::sigmoid(albedo_decoder_(albedo_features, training));
  ag::Variable shape = shape_decoder_(shape_features, training);
  // With the fit's normals as input, the shape branch predicts a correction added to them (a
  // network that outputs 0 there returns the fit); off the fitted face the prior is 0.
  ag::Variable normal = ag::slice_channels(shape, 0, 3);
  if (prior_channels_ > 0) normal = ag::add(normal, ag::slice_channels(images, 3, 3));
  out.normal = ag::l2_normalize(normal);
  out.visibility = ag::slice_channels(shape, 3, 9);
  ag::Variable joint = ag::concat_channels({features, albedo_features, shape_features});
  out.light = light_fc_(ag::global_avg_pool(light_conv_(joint, training)));
  return out;
}

}  // namespace facetool::paper_network
