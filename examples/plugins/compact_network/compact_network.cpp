// compact_network: a small network plugin with the paper's four outputs and a light branch twice
// as wide as the trunk (the paper's is as wide). width C, input S x S:
//   trunk   C3x3 - LReLU - C3x3/2 - LReLU - C3x3 - LReLU          (features at S/2)
//   decoder up2x - C3x3 - LReLU; albedo 1x1->3 sigmoid; shape 1x1->12: normal (3, unit), vis (9)
//   light   1x1 -> 2C - LReLU - average pool - FC 27
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/autograd/functions.h"
#include "core/plugin/network_plugin.h"
#include "core/plugin/plugin_api.h"
#include "core/util/error.h"

namespace {

namespace ag = facetool::ag;
using facetool::Shape;
using facetool::Tensor;
constexpr float kSlope = 0.2f;

class CompactNetwork final : public facetool::NetworkPlugin {
 public:
  void build(facetool::Backend& backend, const facetool::NetworkConfig& config) override {
    facetool::check(config.width >= 2 && config.input_size >= 4 && config.input_size % 2 == 0,
                    "compact_network: width must be >= 2 and input size even and >= 4");
    config_ = config;
    backend_ = &backend;
    params_.clear();
    fan_in_.clear();
    const int64_t c = config.width;
    conv("stem1", 3, c, 3);
    conv("stem2", c, c, 3);
    conv("stem3", c, c, 3);
    conv("decode", c, c, 3);
    conv("albedo", c, 3, 1);
    conv("shape", c, 12, 1);
    conv("light_conv", c, 2 * c, 1);
    add("light_fc.weight", Shape{27, 2 * c}, 2 * c);
    add("light_fc.bias", Shape{27}, 0);
  }
  const facetool::NetworkConfig& config() const override { return config_; }
  std::vector<std::pair<std::string, ag::Variable>> parameters() const override { return params_; }
  std::vector<std::pair<std::string, Tensor>> buffers() const override { return {}; }

  void init_random(uint64_t seed) override {
    // Kaiming-normal weights (Box-Muller on a fixed generator: the same on every platform).
    std::mt19937_64 rng(seed);
    auto uniform = [&rng] { return (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53; };
    for (size_t k = 0; k < params_.size(); ++k) {
      const Tensor& t = params_[k].second.value();
      std::vector<float> values(static_cast<size_t>(t.numel()), 0.0f);
      if (fan_in_[k] > 0) {
        const double sd = std::sqrt(2.0 / (1.0 + kSlope * kSlope) / fan_in_[k]);
        for (float& v : values)
          v = static_cast<float>(sd * std::sqrt(-2.0 * std::log(uniform())) *
                                 std::cos(2.0 * M_PI * uniform()));
      }
      t.copy_from_host(values);
    }
  }

  facetool::NetworkOutputs forward(const ag::Variable& images, bool) override {
    const Shape& s = images.shape();
    facetool::check(s.rank() == 4 && s[1] == 3 && s[2] == config_.input_size &&
                        s[3] == config_.input_size,
                    "compact_network: expected images [N, 3, ", config_.input_size, ", ",
                    config_.input_size, "], got ", s.str());
    ag::Variable h = lrelu(apply("stem1", images));
    h = lrelu(apply("stem2", h, 2));
    const ag::Variable features = lrelu(apply("stem3", h));
    const ag::Variable decoded = lrelu(apply("decode", ag::upsample_bilinear2x(features)));
    facetool::NetworkOutputs out;
    out.albedo = ag::sigmoid(apply("albedo", decoded));
    const ag::Variable shape = apply("shape", decoded);
    out.normal = ag::l2_normalize(ag::slice_channels(shape, 0, 3));
    out.visibility = ag::slice_channels(shape, 3, 9);
    const ag::Variable pooled = ag::global_avg_pool(lrelu(apply("light_conv", features)));
    out.light = ag::linear(pooled, param("light_fc.weight"), param("light_fc.bias"));
    return out;
  }

 private:
  void add(const std::string& name, const Shape& shape, int64_t fan_in) {
    params_.emplace_back(name, ag::Variable(Tensor::zeros(*backend_, shape), true));
    fan_in_.push_back(fan_in);
  }
  void conv(const std::string& name, int64_t in, int64_t out, int64_t k) {
    add(name + ".weight", Shape{out, in, k, k}, in * k * k);
    add(name + ".bias", Shape{out}, 0);
  }
  const ag::Variable& param(const std::string& name) const {
    for (const auto& [n, v] : params_)
      if (n == name) return v;
    facetool::fail("compact_network: no parameter ", name, "; call build() first");
  }
  ag::Variable apply(const std::string& layer, const ag::Variable& x, int stride = 1) const {
    facetool::Conv2dParams p;
    p.stride = stride;
    return ag::conv2d(x, param(layer + ".weight"), param(layer + ".bias"), p);
  }
  static ag::Variable lrelu(const ag::Variable& x) { return ag::leaky_relu(x, kSlope); }

  facetool::NetworkConfig config_;
  facetool::Backend* backend_ = nullptr;
  std::vector<std::pair<std::string, ag::Variable>> params_;
  std::vector<int64_t> fan_in_;
};

}  // namespace

FACETOOL_DEFINE_PLUGIN(CompactNetwork, FACETOOL_PLUGIN_NETWORK, "compact_network", "1.0.0",
                       "a compact network with the paper's outputs and a light branch 2x as wide")
