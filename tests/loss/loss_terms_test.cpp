// The paper_losses plugin against double-precision references, finite differences and blocking.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "core/autograd/functions.h"
#include "core/backend/registry.h"
#include "core/plugin/loss_plugin.h"
#include "core/plugin/plugin_loader.h"
#include "core/util/error.h"
#include "loss_reference.h"
#include "tests/support/finite_difference.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

const char* const kTerms[] = {"albedo",       "normal",       "visibility",
                              "light",        "recon_albedo", "recon_normal",
                              "recon_visibility", "recon_light", "recon_albedo_normal_light",
                              "recon_all"};

struct Plugins {
  PluginLoader loader;
  std::shared_ptr<Plugin> losses, renderer, network_factory;
  Plugins() {
    losses = loader.create(loader.load_file(FACETOOL_PAPER_LOSSES_PLUGIN));
    renderer = loader.create(loader.load_file(FACETOOL_SH_RENDERER_PLUGIN));
    loader.load_file(FACETOOL_PAPER_NETWORK_PLUGIN);
  }
  LossPlugin& loss() { return dynamic_cast<LossPlugin&>(*losses); }
  RendererPlugin& render() { return dynamic_cast<RendererPlugin&>(*renderer); }
  std::shared_ptr<NetworkPlugin> network() {
    return std::dynamic_pointer_cast<NetworkPlugin>(
        loader.create(loader.find(FACETOOL_PLUGIN_NETWORK, "paper_network")));
  }
};

Plugins& plugins() {
  static Plugins p;
  return p;
}

HostParts random_parts(int64_t n, int64_t pixels, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  HostParts s;
  s.albedo.resize(n * 3 * pixels);
  for (double& a : s.albedo) a = 0.1 + 0.9 * u(rng);
  s.normal.resize(n * 3 * pixels);
  for (int64_t i = 0; i < n; ++i)
    for (int64_t p = 0; p < pixels; ++p) {
      double d[3] = {g(rng), g(rng), std::fabs(g(rng)) + 0.5}, len = 0.0;
      for (double x : d) len += x * x;
      for (int a = 0; a < 3; ++a) s.normal[(i * 3 + a) * pixels + p] = d[a] / std::sqrt(len);
    }
  s.visibility.resize(n * 9 * pixels);
  for (int64_t i = 0; i < n * 9 * pixels; ++i)
    s.visibility[i] = (i / pixels) % 9 == 0 ? 1.5 + 2.0 * u(rng) : u(rng) - 0.5;
  s.light.resize(n * 27);
  for (int64_t i = 0; i < n * 27; ++i) s.light[i] = i % 9 == 0 ? 1.0 + 2.0 * u(rng) : 2.0 * u(rng) - 1.0;
  return s;
}

struct Case {
  HostBatch batch;
  HostParts predicted;
};

// Two images of 3 x 4 pixels, each with two pixels outside the mask.
Case random_case(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Case c;
  HostBatch& b = c.batch;
  b.n = 2, b.h = 3, b.w = 4;
  const int64_t pixels = b.h * b.w;
  b.target = random_parts(b.n, pixels, rng);
  c.predicted = random_parts(b.n, pixels, rng);
  b.image.resize(b.n * 3 * pixels);
  for (double& x : b.image) x = u(rng);
  b.mask.assign(b.n * pixels, 1.0);
  b.mask[1] = b.mask[7] = b.mask[pixels + 2] = b.mask[pixels + 11] = 0.0;
  return c;
}

std::vector<float> to_float(const std::vector<double>& v) { return {v.begin(), v.end()}; }
Tensor upload(Backend& be, const Shape& s, const std::vector<double>& v) {
  return Tensor::from_host(be, s, to_float(v));
}

LossTargets upload_targets(Backend& be, const HostBatch& b) {
  LossTargets t;
  t.image = upload(be, Shape{b.n, 3, b.h, b.w}, b.image);
  t.albedo = upload(be, Shape{b.n, 3, b.h, b.w}, b.target.albedo);
  t.normal = upload(be, Shape{b.n, 3, b.h, b.w}, b.target.normal);
  t.visibility = upload(be, Shape{b.n, 9, b.h, b.w}, b.target.visibility);
  t.light = upload(be, Shape{b.n, 27}, b.target.light);
  t.mask = upload(be, Shape{b.n, 1, b.h, b.w}, b.mask);
  return t;
}

// The predicted parts as leaves that collect gradients.
NetworkOutputs upload_predicted(Backend& be, const HostBatch& b, const HostParts& p) {
  NetworkOutputs o;
  o.albedo = ag::Variable(upload(be, Shape{b.n, 3, b.h, b.w}, p.albedo), true);
  o.normal = ag::Variable(upload(be, Shape{b.n, 3, b.h, b.w}, p.normal), true);
  o.visibility = ag::Variable(upload(be, Shape{b.n, 9, b.h, b.w}, p.visibility), true);
  o.light = ag::Variable(upload(be, Shape{b.n, 27}, p.light), true);
  return o;
}

std::vector<double>& part(HostParts& p, int c) {
  std::vector<double>* all[4] = {&p.albedo, &p.normal, &p.visibility, &p.light};
  return *all[c];
}
const ag::Variable& part(const NetworkOutputs& o, int c) {
  const ag::Variable* all[4] = {&o.albedo, &o.normal, &o.visibility, &o.light};
  return *all[c];
}

// Which predicted parts a term differentiates (albedo, normal, visibility, light).
std::vector<int> differentiated(const std::string& term) {
  if (term == "albedo" || term == "recon_albedo") return {0};
  if (term == "normal" || term == "recon_normal") return {1};
  if (term == "visibility" || term == "recon_visibility") return {2};
  if (term == "light" || term == "recon_light") return {3};
  if (term == "recon_albedo_normal_light") return {0, 1, 3};
  return {0, 1, 2, 3};
}

TEST(PaperLosses, ListsEveryTermOfThePaper) {
  std::vector<std::string> names;
  for (const LossTermInfo& t : plugins().loss().terms()) names.push_back(t.name);
  for (const char* term : kTerms)
    EXPECT_NE(std::find(names.begin(), names.end(), term), names.end()) << term;
}

// Every term's value against the double-precision reference, on every backend.
TEST(PaperLosses, ValuesMatchDoublePrecisionReference) {
  const Case c = random_case(11);
  std::vector<std::string> backends = non_reference_backends();
  backends.insert(backends.begin(), "cpu");
  for (const std::string& name : backends) {
    Backend& be = get_backend(name);
    const LossTargets targets = upload_targets(be, c.batch);
    const NetworkOutputs predicted = upload_predicted(be, c.batch, c.predicted);
    for (const char* term : kTerms) {
      const double expected = reference_term(term, c.batch, c.predicted);
      const double actual =
          plugins().loss().evaluate(term, predicted, targets, plugins().render()).value().to_host()[0];
      EXPECT_GT(expected, 1e-3) << term;  // a meaningful comparison, not 0 == 0
      EXPECT_NEAR(actual, expected, 2e-5 * expected) << term << " on " << name;
    }
  }
}

// Gradients to each differentiated input against central differences of the reference (h =
// 1e-6 in double); inputs a term does not differentiate receive no gradient.
TEST(PaperLosses, GradientsMatchFiniteDifferencesOfReference) {
  const Case c = random_case(12);
  Backend& be = get_backend("cpu");
  const LossTargets targets = upload_targets(be, c.batch);
  for (const char* term : kTerms) {
    const NetworkOutputs predicted = upload_predicted(be, c.batch, c.predicted);
    plugins().loss().evaluate(term, predicted, targets, plugins().render()).backward();
    const std::vector<int> wanted = differentiated(term);
    for (int k = 0; k < 4; ++k) {
      const bool want = std::find(wanted.begin(), wanted.end(), k) != wanted.end();
      ASSERT_EQ(part(predicted, k).has_grad(), want) << term << " input " << k;
      if (!want) continue;
      HostParts moved = c.predicted;
      std::vector<double>& values = part(moved, k);
      std::vector<double> fd(values.size());
      double largest = 0.0;
      for (size_t i = 0; i < values.size(); ++i) {
        fd[i] = central_difference(values[i], 1e-6, [&] { return reference_term(term, c.batch, moved); });
        largest = std::max(largest, std::fabs(fd[i]));
      }
      ASSERT_GT(largest, 1e-4) << term << " input " << k;
      EXPECT_TRUE(all_close(part(predicted, k).grad().to_host(), to_float(fd), 2e-4 * largest, 2e-3))
          << term << " input " << k;
    }
  }
}

// E_recon-rho,n,L: visibility gets no gradient; albedo, normal and light get exactly what the
// four-variate term gives them.
TEST(PaperLosses, ThreeVariateBlocksVisibilityAndKeepsOtherGradients) {
  const Case c = random_case(13);
  Backend& be = get_backend("cpu");
  const LossTargets targets = upload_targets(be, c.batch);
  const NetworkOutputs three = upload_predicted(be, c.batch, c.predicted);
  const NetworkOutputs four = upload_predicted(be, c.batch, c.predicted);
  const ag::Variable e3 =
      plugins().loss().evaluate("recon_albedo_normal_light", three, targets, plugins().render());
  const ag::Variable e4 = plugins().loss().evaluate("recon_all", four, targets, plugins().render());
  EXPECT_EQ(e3.value().to_host()[0], e4.value().to_host()[0]);
  e3.backward();
  e4.backward();
  EXPECT_FALSE(three.visibility.has_grad());
  ASSERT_TRUE(four.visibility.has_grad());
  double largest = 0.0;
  for (float g : four.visibility.grad().to_host()) largest = std::max(largest, double(std::fabs(g)));
  EXPECT_GT(largest, 1e-4);  // the four-variate term does move visibility
  for (int k : {0, 1, 3})
    EXPECT_TRUE(all_close(part(three, k).grad().to_host(), part(four, k).grad().to_host(), 0.0, 1e-6))
        << "input " << k;
}

// Through the network: the three-variate term leaves the visibility outputs' weights (channels
// 3..11 of the shape decoder's last convolution) with zero gradient; the four-variate one does not.
TEST(PaperLosses, ThreeVariateLeavesNetworkVisibilityBranchUntouched) {
  Backend& be = get_backend("cpu");
  for (const char* term : {"recon_albedo_normal_light", "recon_all"}) {
    std::shared_ptr<NetworkPlugin> net = plugins().network();
    net->build(be, NetworkConfig{4, 8});
    net->init_random(5);
    // Random targets of the network's 8 x 8 size.
    HostBatch b;
    b.n = 2, b.h = 8, b.w = 8;
    std::mt19937 rng(15);
    b.target = random_parts(2, 64, rng);
    b.image.assign(2 * 3 * 64, 0.5);
    b.mask.assign(2 * 64, 1.0);
    const LossTargets targets = upload_targets(be, b);
    const ag::Variable images(random_tensor(be, Shape{2, 3, 8, 8}, 16, 0.0f, 1.0f));
    const NetworkOutputs out = net->forward(images, true);
    plugins().loss().evaluate(term, out, targets, plugins().render()).backward();
    bool found = false;
    for (const auto& [name, p] : net->parameters()) {
      if (name != "shape_decoder.out.weight" && name != "shape_decoder.out.bias") continue;
      found = true;
      ASSERT_TRUE(p.has_grad()) << name;
      const std::vector<float> g = p.grad().to_host();
      const int64_t per_row = static_cast<int64_t>(g.size()) / 12;
      double normal_rows = 0.0, visibility_rows = 0.0;
      for (int64_t i = 0; i < static_cast<int64_t>(g.size()); ++i)
        (i / per_row < 3 ? normal_rows : visibility_rows) += std::fabs(g[i]);
      EXPECT_GT(normal_rows, 0.0) << term << " " << name;
      if (std::string(term) == "recon_all")
        EXPECT_GT(visibility_rows, 0.0) << name;
      else
        EXPECT_EQ(visibility_rows, 0.0) << name;
    }
    EXPECT_TRUE(found) << "the shape decoder's output convolution was not found";
  }
}

// E_L computed through the 9x9 Gram matrix equals the explicit 64,000-direction mean.
TEST(PaperLosses, LightLossGramMatrixEqualsExplicitDirectionSum) {
  Backend& be = get_backend("cpu");
  for (unsigned seed : {21u, 22u, 23u}) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 2.0);
    std::vector<double> a(4 * 27), b(4 * 27);
    for (double& x : a) x = g(rng);
    for (double& x : b) x = g(rng);
    NetworkOutputs predicted;
    predicted.light = ag::Variable(upload(be, Shape{4, 27}, a), true);
    LossTargets targets;
    targets.light = upload(be, Shape{4, 27}, b);
    targets.mask = Tensor::full(be, Shape{4, 1, 1, 1}, 1.0f);
    // The reference sees the float-rounded lights the plugin sees.
    std::vector<double> af(a.begin(), a.end()), bf(b.begin(), b.end());
    for (double& x : af) x = static_cast<float>(x);
    for (double& x : bf) x = static_cast<float>(x);
    const double expected = reference_light_loss(af, bf);
    const double actual =
        plugins().loss().evaluate("light", predicted, targets, plugins().render()).value().to_host()[0];
    EXPECT_NEAR(actual, expected, 1e-6 * expected) << "seed " << seed;
  }
}

TEST(PaperLosses, MissingTargetAndUnknownTermAreClearErrors) {
  const Case c = random_case(17);
  Backend& be = get_backend("cpu");
  LossTargets targets = upload_targets(be, c.batch);
  targets.visibility = Tensor();  // a real photo without pseudo labels
  const NetworkOutputs predicted = upload_predicted(be, c.batch, c.predicted);
  try {
    plugins().loss().evaluate("recon_albedo", predicted, targets, plugins().render());
    FAIL() << "no error for a missing target";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("visibility"), std::string::npos) << e.what();
  }
  // The three-variate term needs only the image: it still works.
  EXPECT_NO_THROW(plugins().loss().evaluate("recon_albedo_normal_light", predicted, targets,
                                            plugins().render()));
  try {
    plugins().loss().evaluate("recon_everything", predicted, targets, plugins().render());
    FAIL() << "no error for an unknown term";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("recon_everything"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace facetool::testing
