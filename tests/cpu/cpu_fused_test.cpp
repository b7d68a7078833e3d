// The cpu backend's fused inference ops against the plain reference (ops::conv2d and host loops):
// every convolution algorithm (im2col, Winograd, oneDNN, direct) with every epilogue on odd shapes.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "backends/cpu/cpu_conv.h"
#include "backends/cpu/cpu_conv_choice.h"
#include "core/backend/registry.h"
#include "core/ops/ops.h"
#include "core/util/error.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

using cpu::ConvAlgorithm;

Backend& cpu_backend() { return get_backend("cpu"); }

// Forces one algorithm for the lifetime of the object.
struct ForcedAlgorithm {
  explicit ForcedAlgorithm(ConvAlgorithm a) { cpu::set_conv_algorithm_override(a); }
  ~ForcedAlgorithm() { cpu::set_conv_algorithm_override(std::nullopt); }
};

struct Case {
  int64_t batch, in, out, size, kernel;
  int stride;
};

// Channels 1, 3, 13, 31, 33; sizes 1, 7, 64, 65; batches 1 and 20; kernels 1, 3, 7; stride 2.
const Case kCases[] = {
    {1, 1, 3, 7, 3, 1},    {20, 3, 13, 7, 3, 1},  {1, 13, 31, 64, 3, 1}, {20, 31, 33, 7, 3, 1},
    {1, 33, 33, 65, 3, 1}, {20, 33, 1, 1, 3, 1},  {1, 3, 13, 65, 7, 1},  {20, 13, 3, 7, 1, 1},
    {1, 31, 13, 64, 1, 1}, {20, 33, 31, 7, 3, 2}, {1, 13, 33, 65, 3, 2}, {20, 1, 31, 1, 7, 1},
    {20, 33, 33, 64, 3, 1}};

std::string describe(const Case& c, ConvAlgorithm a, int variant) {
  return std::to_string(c.batch) + "x" + std::to_string(c.in) + "x" + std::to_string(c.size) +
         " k" + std::to_string(c.kernel) + " s" + std::to_string(c.stride) + " -> " +
         std::to_string(c.out) + " by " + cpu::conv_algorithm_name(a) + ", epilogue " +
         std::to_string(variant);
}

// Each output sums up to in * kernel^2 products of values in [-1, 1]; float rounding of the
// algorithms (Winograd's transforms most) stays well inside these.
constexpr double kAtol = 5e-4, kRtol = 1e-4;

TEST(CpuFused, ConvolutionWithEveryEpilogueMatchesThePlainReference) {
  Backend& be = cpu_backend();
  unsigned seed = 100;
  for (const Case& c : kCases) {
    const Shape xs{c.batch, c.in, c.size, c.size}, ws{c.out, c.in, c.kernel, c.kernel};
    const Tensor x = random_tensor(be, xs, ++seed);
    const Tensor w = random_tensor(be, ws, ++seed);
    const Tensor y_shape = ops::conv2d(x, w, nullptr, Conv2dParams{c.stride});
    const Shape ys = y_shape.shape();
    const Tensor scale = random_tensor(be, Shape{c.out}, ++seed, 0.5f, 1.5f);
    const Tensor shift = random_tensor(be, Shape{c.out}, ++seed);
    const Tensor post_scale = random_tensor(be, Shape{c.out}, ++seed, 0.5f, 1.5f);
    const Tensor post_shift = random_tensor(be, Shape{c.out}, ++seed);
    const Tensor residual = random_tensor(be, ys, ++seed);
    for (int variant = 0; variant < 4; ++variant) {
      ConvEpilogue e;
      if (variant == 0) {  // bias only
        e.shift = &shift;
      } else if (variant == 1) {  // folded batch norm + leaky ReLU
        e.scale = &scale;
        e.shift = &shift;
        e.activation = ConvEpilogue::Activation::LeakyRelu;
        e.slope = 0.2f;
      } else if (variant == 2) {  // sigmoid output layer
        e.shift = &shift;
        e.activation = ConvEpilogue::Activation::Sigmoid;
      } else {  // residual block's last convolution with the next batch norm as second output
        e.shift = &shift;
        e.residual = &residual;
        e.post_scale = &post_scale;
        e.post_shift = &post_shift;
        e.post_slope = 0.2f;
      }
      Tensor y2_expected = Tensor::empty(be, ys);
      ConvEpilogue reference = e;
      if (variant == 3) reference.y2 = &y2_expected;
      const std::vector<float> expected =
          ops::conv2d_fused_reference(x, w, Conv2dParams{c.stride}, reference).to_host();
      for (ConvAlgorithm a : cpu::applicable_conv_algorithms(
               cpu::ConvGeometry{c.in, c.size, c.size, c.kernel, c.stride, c.kernel / 2,
                                 ys.h(), ys.w()},
               c.out)) {
        ForcedAlgorithm forced(a);
        Tensor y2 = Tensor::empty(be, ys);
        ConvEpilogue fused = e;
        if (variant == 3) fused.y2 = &y2;
        const Tensor y = ops::conv2d_fused(x, w, Conv2dParams{c.stride}, fused);
        EXPECT_TRUE(all_close(y.to_host(), expected, kAtol, kRtol)) << describe(c, a, variant);
        if (variant == 3) {
          EXPECT_TRUE(all_close(y2.to_host(), y2_expected.to_host(), kAtol, kRtol))
              << describe(c, a, variant) << " second output";
        }
      }
    }
  }
}

// The direct algorithm (stride 1, tap by tap from a padded copy) where the square cases above do
// not reach: non-square images, padding below, at and above "same", dlib's face detector's last
// layer (45 channels, 9x9, into one), and output channels in whole and partial groups of four.
TEST(CpuFused, DirectConvolutionOnNonSquareImagesAndAnyPaddingMatchesThePlainReference) {
  Backend& be = cpu_backend();
  struct DirectCase {
    int64_t batch, in, out, height, width, kernel;
    int pad;
  };
  const DirectCase cases[] = {{1, 45, 1, 139, 37, 9, 4}, {2, 3, 2, 13, 40, 5, 2}, {3, 13, 5, 7, 33, 3, 0},
                              {1, 1, 9, 1, 17, 3, 2},    {2, 31, 4, 20, 3, 5, 4}, {1, 4, 7, 65, 9, 1, 0},
                              {20, 3, 3, 9, 8, 7, 3}};
  unsigned seed = 500;
  for (const DirectCase& c : cases) {
    const Conv2dParams params{1, c.pad};
    const Tensor x = random_tensor(be, Shape{c.batch, c.in, c.height, c.width}, ++seed);
    // Weights in [-0.1, 0.1]: sums of up to 3,645 products stay near 1, where kAtol is strict.
    const Tensor w = random_tensor(be, Shape{c.out, c.in, c.kernel, c.kernel}, ++seed, -0.1f, 0.1f);
    const Tensor scale = random_tensor(be, Shape{c.out}, ++seed, 0.5f, 1.5f);
    const Tensor shift = random_tensor(be, Shape{c.out}, ++seed);
    ConvEpilogue e;
    e.scale = &scale;
    e.shift = &shift;
    e.activation = ConvEpilogue::Activation::LeakyRelu;
    e.slope = 0.2f;
    const std::vector<float> expected = ops::conv2d_fused_reference(x, w, params, e).to_host();
    const std::string what = std::to_string(c.batch) + "x" + std::to_string(c.in) + "x" + std::to_string(c.height) +
                             "x" + std::to_string(c.width) + " k" + std::to_string(c.kernel) + " pad " +
                             std::to_string(c.pad) + " -> " + std::to_string(c.out);
    const int64_t out_h = c.height + 2 * c.pad - c.kernel + 1, out_w = c.width + 2 * c.pad - c.kernel + 1;
    ASSERT_TRUE(cpu::direct_conv_applicable(
        cpu::ConvGeometry{c.in, c.height, c.width, c.kernel, 1, c.pad, out_h, out_w}))
        << what;  // else the forced algorithm would fall back and this test compare nothing new
    ForcedAlgorithm forced(ConvAlgorithm::Direct);
    const Tensor y = ops::conv2d_fused(x, w, params, e);
    ASSERT_EQ(y.shape(), (Shape{c.batch, c.out, out_h, out_w})) << what;
    EXPECT_TRUE(all_close(y.to_host(), expected, kAtol, kRtol)) << what;
  }
  // Stride 2 and a padding that does not give the output's size are refused.
  EXPECT_FALSE(cpu::direct_conv_applicable(cpu::ConvGeometry{3, 8, 8, 3, 2, 1, 4, 4}));
  EXPECT_FALSE(cpu::direct_conv_applicable(cpu::ConvGeometry{3, 8, 8, 3, 1, 1, 7, 8}));
}

// Every convolution of the paper network (plugins/paper_network) at width c and input s, as
// {in, out, kernel, stride, size}: stem 7x7 and 3x3, the stride-2 layer, residual, decoder 3x3
// layers, the 1x1 output layers and the light head's 1x1.
std::vector<std::array<int64_t, 5>> network_layer_shapes(int64_t c, int64_t s) {
  return {{3, c / 2, 7, 1, s}, {c / 2, c, 3, 1, s}, {c, c, 3, 2, s}, {c, c, 3, 1, s / 2},
          {c, c, 3, 1, s},     {c, c / 2, 3, 1, s}, {c / 2, 12, 1, 1, s}, {c / 2, 3, 1, 1, s},
          {3 * c, c, 1, 1, s / 2}};
}

// Each algorithm at batch 1 (its own task split over the threads: an image's pixels or tiles cut
// into as many equal parts as there are threads) gives every image what a batch of 3 gives it,
// epilogue included, on every layer shape of the shipped network (width 32 at 96 x 96 and 64 x 64)
// and of the paper's (128 at 128 x 128), and at odd sizes (width 26 at 50: 13 channels, a 25 x 25
// residual stage; width 14 at 66). The same sums in blocks of other lengths: float rounding of up
// to 1152 products of values in [-1, 1].
TEST(CpuFused, BatchOneGivesEachImageTheBatchsOutputsOnEveryLayerShape) {
  Backend& be = cpu_backend();
  constexpr int64_t kBatch = 3;
  unsigned seed = 900;
  for (const auto& [width, size] : {std::pair<int64_t, int64_t>{32, 96}, {32, 64}, {128, 128},
                                    {26, 50}, {14, 66}}) {
    for (const auto& [in, out, kernel, stride, s] : network_layer_shapes(width, size)) {
      const Tensor x = random_tensor(be, Shape{kBatch, in, s, s}, ++seed);
      const Tensor w = random_tensor(be, Shape{out, in, kernel, kernel}, ++seed);
      const Conv2dParams params{static_cast<int>(stride)};
      const Shape ys = ops::conv2d(random_tensor(be, Shape{1, in, s, s}, 1), w, nullptr, params)
                           .shape();
      const Tensor scale = random_tensor(be, Shape{out}, ++seed, 0.5f, 1.5f);
      const Tensor shift = random_tensor(be, Shape{out}, ++seed);
      const Tensor residual = random_tensor(be, Shape{kBatch, out, ys.h(), ys.w()}, ++seed);
      const std::vector<float> xs = x.to_host(), rs = residual.to_host();
      const cpu::ConvGeometry g{in, s, s, kernel, stride, kernel / 2, ys.h(), ys.w()};
      for (ConvAlgorithm a : cpu::applicable_conv_algorithms(g, out)) {
        if (a == ConvAlgorithm::Direct) continue;  // the rule takes it for no layer here
        ForcedAlgorithm forced(a);
        // conv -> scale, shift, + residual, leaky ReLU; the same again as a second output
        auto run = [&](const Tensor& images, const Tensor& added, std::vector<float>& second) {
          ConvEpilogue e;
          e.scale = &scale;
          e.shift = &shift;
          e.residual = &added;
          e.activation = ConvEpilogue::Activation::LeakyRelu;
          e.slope = 0.2f;
          Tensor y2 = Tensor::empty(be, Shape{images.shape().n(), out, ys.h(), ys.w()});
          e.y2 = &y2;
          e.post_scale = &scale;
          e.post_shift = &shift;
          e.post_slope = 0.1f;
          const std::vector<float> y = ops::conv2d_fused(images, w, params, e).to_host();
          second = y2.to_host();
          return y;
        };
        std::vector<float> batch_second;
        const std::vector<float> batch_y = run(x, residual, batch_second);
        const size_t in_floats = xs.size() / kBatch, out_floats = batch_y.size() / kBatch;
        for (int64_t n = 0; n < kBatch; ++n) {
          Tensor one = Tensor::empty(be, Shape{1, in, s, s});
          one.copy_from_host(std::vector<float>(xs.begin() + n * in_floats,
                                                xs.begin() + (n + 1) * in_floats));
          Tensor one_residual = Tensor::empty(be, Shape{1, out, ys.h(), ys.w()});
          one_residual.copy_from_host(std::vector<float>(rs.begin() + n * out_floats,
                                                         rs.begin() + (n + 1) * out_floats));
          std::vector<float> second;
          const std::vector<float> y = run(one, one_residual, second);
          const std::string what = std::to_string(in) + "->" + std::to_string(out) + " k" +
                                   std::to_string(kernel) + " s" + std::to_string(stride) +
                                   " at " + std::to_string(s) + " by " +
                                   cpu::conv_algorithm_name(a) + ", image " + std::to_string(n);
          const auto part = [&](const std::vector<float>& v) {
            return std::vector<float>(v.begin() + n * out_floats, v.begin() + (n + 1) * out_floats);
          };
          EXPECT_TRUE(all_close(y, part(batch_y), 1e-4, 1e-5)) << what;
          EXPECT_TRUE(all_close(second, part(batch_second), 1e-4, 1e-5)) << what << " second output";
        }
      }
    }
  }
}

// Inference keeps Winograd's transformed weights between calls (cpu_weight_cache.h): weights
// changed in place, at the same address, are transformed anew.
TEST(CpuFused, WinogradWeightsChangedInPlaceAreTransformedAnew) {
  Backend& be = cpu_backend();
  ForcedAlgorithm forced(ConvAlgorithm::Winograd);
  const Tensor x = random_tensor(be, Shape{1, 16, 12, 12}, 31);
  const Tensor w = random_tensor(be, Shape{16, 16, 3, 3}, 32);
  for (unsigned version = 0; version < 3; ++version) {
    if (version > 0) w.copy_from_host(random_values(static_cast<size_t>(w.numel()), 40 + version));
    const std::vector<float> y = ops::conv2d_fused(x, w, Conv2dParams{}, ConvEpilogue{}).to_host();
    const std::vector<float> expected =
        ops::conv2d_fused_reference(x, w, Conv2dParams{}, ConvEpilogue{}).to_host();
    EXPECT_TRUE(all_close(y, expected, kAtol, kRtol)) << "weights version " << version;
  }
}

// The rule without measurements: direct for a stride-1 kernel over 1x1 with few outputs.
TEST(CpuFused, DefaultRuleTakesDirectForFewOutputChannelsOnly) {
  const cpu::ConvGeometry last{45, 139, 37, 9, 1, 4, 139, 37}, pointwise{16, 96, 96, 1, 1, 0, 96, 96};
  EXPECT_EQ(cpu::default_conv_algorithm(last, 1), ConvAlgorithm::Direct);
  EXPECT_EQ(cpu::default_conv_algorithm(last, cpu::kDirectMaxOutChannels), ConvAlgorithm::Direct);
  EXPECT_EQ(cpu::default_conv_algorithm(last, cpu::kDirectMaxOutChannels + 1), ConvAlgorithm::Im2col);
  EXPECT_EQ(cpu::default_conv_algorithm(pointwise, 3), ConvAlgorithm::Im2col);
  EXPECT_EQ(cpu::default_conv_algorithm(cpu::ConvGeometry{32, 48, 48, 3, 1, 1, 48, 48}, 32), ConvAlgorithm::Winograd);
}

TEST(CpuFused, PlainPathsSwitchIsHonoured) {
  // With fused paths off, conv2d_fused is the reference itself (bit for bit).
  Backend& be = cpu_backend();
  const Tensor x = random_tensor(be, Shape{2, 13, 7, 7}, 1);
  const Tensor w = random_tensor(be, Shape{31, 13, 3, 3}, 2);
  const Tensor shift = random_tensor(be, Shape{31}, 3);
  ConvEpilogue e;
  e.shift = &shift;
  e.activation = ConvEpilogue::Activation::LeakyRelu;
  e.slope = 0.2f;
  ops::set_fused_paths_enabled(false);
  const std::vector<float> plain = ops::conv2d_fused(x, w, Conv2dParams{}, e).to_host();
  ops::set_fused_paths_enabled(true);
  EXPECT_EQ(plain, ops::conv2d_fused_reference(x, w, Conv2dParams{}, e).to_host());
}

TEST(CpuFused, AffineLeakyReluMatchesBatchNormThenLeakyRelu) {
  Backend& be = cpu_backend();
  for (const int64_t channels : {1, 3, 13, 31, 33}) {
    for (const int64_t size : {1, 7, 64, 65}) {
      for (const int64_t batch : {1, 20}) {
        if (batch == 20 && size >= 64 && channels > 3) continue;  // keep the test quick
        const Shape xs{batch, channels, size, size}, cs{channels};
        const Tensor x = random_tensor(be, xs, 7);
        const Tensor gamma = random_tensor(be, cs, 8, 0.5f, 1.5f);
        const Tensor beta = random_tensor(be, cs, 9);
        const Tensor mean = random_tensor(be, cs, 10);
        const Tensor var = random_tensor(be, cs, 11, 0.1f, 2.0f);
        BatchNormParams eval;
        eval.training = false;
        const std::vector<float> expected =
            ops::leaky_relu(ops::batch_norm(x, gamma, beta, mean, var, eval), 0.2f).to_host();
        Tensor scale, shift;
        ops::fold_batch_norm(gamma, beta, mean, var, eval.eps, nullptr, scale, shift);
        EXPECT_TRUE(all_close(ops::channel_affine_leaky_relu(x, scale, shift, 0.2f).to_host(),
                              expected, 1e-5, 1e-5))
            << batch << "x" << channels << "x" << size;
      }
    }
  }
}

TEST(CpuFused, FoldedBatchNormMatchesConvolutionThenBatchNorm) {
  Backend& be = cpu_backend();
  const Shape xs{3, 13, 9, 9}, ws{31, 13, 3, 3}, cs{31};
  const Tensor x = random_tensor(be, xs, 1), w = random_tensor(be, ws, 2);
  const Tensor bias = random_tensor(be, cs, 3), gamma = random_tensor(be, cs, 4, 0.5f, 1.5f);
  const Tensor beta = random_tensor(be, cs, 5), mean = random_tensor(be, cs, 6);
  const Tensor var = random_tensor(be, cs, 7, 0.1f, 2.0f);
  BatchNormParams eval;
  eval.training = false;
  const std::vector<float> expected =
      ops::batch_norm(ops::conv2d(x, w, &bias, Conv2dParams{}), gamma, beta, mean, var, eval)
          .to_host();
  Tensor scale, shift;
  ops::fold_batch_norm(gamma, beta, mean, var, eval.eps, &bias, scale, shift);
  ConvEpilogue e;
  e.scale = &scale;
  e.shift = &shift;
  EXPECT_TRUE(all_close(ops::conv2d_fused(x, w, Conv2dParams{}, e).to_host(), expected, 1e-4,
                        1e-4));
}

TEST(CpuFused, MismatchedEpilogueShapesAreRefused) {
  Backend& be = cpu_backend();
  const Tensor x = random_tensor(be, Shape{1, 3, 5, 5}, 1);
  const Tensor w = random_tensor(be, Shape{4, 3, 3, 3}, 2);
  const Tensor wrong = random_tensor(be, Shape{5}, 3);
  ConvEpilogue e;
  e.shift = &wrong;
  EXPECT_THROW(ops::conv2d_fused(x, w, Conv2dParams{}, e), Error);
  const Tensor y2 = Tensor::empty(be, Shape{1, 4, 5, 5});
  ConvEpilogue missing;
  missing.y2 = &y2;  // without post_scale / post_shift
  EXPECT_THROW(ops::conv2d_fused(x, w, Conv2dParams{}, missing), Error);
}

// Batch norm + leaky ReLU in one pass (forward) and its backward reading the activation's sign
// from the output, against the plain ops (batch_norm, leaky_relu and their backwards), in
// training and eval mode, overwriting and accumulating gradients.
TEST(CpuFused, BatchNormLeakyReluForwardAndBackwardMatchThePlainOps) {
  Backend& be = cpu_backend();
  unsigned seed = 300;
  for (const int64_t channels : {1, 3, 13, 31, 33}) {
    for (const int64_t size : {1, 7, 64, 65}) {
      for (const int64_t batch : {1, 20}) {
        if (batch == 20 && size >= 64 && channels > 3) continue;  // keep the test quick
        for (const bool training : {true, false}) {
          if (training && batch * size * size < 2) continue;  // needs two values per channel
          const Shape xs{batch, channels, size, size}, cs{channels};
          const Tensor x = random_tensor(be, xs, ++seed);
          const Tensor gamma = random_tensor(be, cs, ++seed, 0.5f, 1.5f);
          const Tensor beta = random_tensor(be, cs, ++seed);
          const Tensor dy = random_tensor(be, xs, ++seed);
          const std::vector<float> mean0 = random_values(channels, ++seed, -0.2f, 0.2f),
                                   var0 = random_values(channels, ++seed, 0.5f, 2.0f);
          BatchNormParams p;
          p.training = training;
          struct Result {
            std::vector<float> y, dx, dgamma, dbeta, mean, var;
          };
          auto run = [&](bool fused, bool accumulate) {
            ops::set_fused_paths_enabled(fused);
            const Tensor mean = Tensor::from_host(be, cs, mean0);
            const Tensor var = Tensor::from_host(be, cs, var0);
            ops::BatchNormSaved saved;
            const Tensor y = ops::batch_norm_leaky_relu(x, gamma, beta, mean, var, p, 0.2f, &saved);
            const Tensor dx = Tensor::full(be, xs, 0.5f);
            const Tensor dgamma = Tensor::full(be, cs, 0.5f), dbeta = Tensor::full(be, cs, 0.5f);
            ops::batch_norm_leaky_relu_backward(x, gamma, saved, y, 0.2f, dy, &dx, &dgamma,
                                                &dbeta, p, accumulate);
            ops::set_fused_paths_enabled(true);
            return Result{y.to_host(),      dx.to_host(),   dgamma.to_host(),
                          dbeta.to_host(),  mean.to_host(), var.to_host()};
          };
          const std::string what = std::to_string(batch) + "x" + std::to_string(channels) + "x" +
                                   std::to_string(size) + (training ? " training" : " eval");
          for (const bool accumulate : {false, true}) {
            const Result fused = run(true, accumulate), plain = run(false, accumulate);
            const std::string w = what + (accumulate ? " accumulate" : "");
            EXPECT_TRUE(all_close(fused.y, plain.y, 1e-6, 1e-5)) << w << " y";
            EXPECT_TRUE(all_close(fused.dx, plain.dx, 1e-5, 1e-4)) << w << " dx";
            // dgamma and dbeta sum over batch * size^2 values.
            const double atol = 1e-5 * std::sqrt(double(batch * size * size));
            EXPECT_TRUE(all_close(fused.dgamma, plain.dgamma, atol, 1e-4)) << w << " dgamma";
            EXPECT_TRUE(all_close(fused.dbeta, plain.dbeta, atol, 1e-4)) << w << " dbeta";
            EXPECT_EQ(fused.mean, plain.mean) << w << " running mean";
            EXPECT_EQ(fused.var, plain.var) << w << " running var";
          }
        }
      }
    }
  }
}

// The optimiser's fused step over all parameters against one adam_step per parameter: the same
// bits (the trainer's exact resume relies on it), on sizes that cut chunks mid-parameter.
TEST(CpuFused, AdamOverAllParametersEqualsOneStepPerParameter) {
  Backend& be = cpu_backend();
  const std::vector<int64_t> sizes{1, 3, 13, 31, 33, 16385, 64, 40000, 65};
  std::vector<Backend::AdamTensors> fused, single;
  unsigned seed = 500;
  for (const int64_t n : sizes) {
    const Shape s{n};
    const std::vector<float> param = random_values(n, ++seed), grad = random_values(n, ++seed),
                             m = random_values(n, ++seed, -0.1f, 0.1f),
                             v = random_values(n, ++seed, 0.0f, 0.1f);
    for (auto* list : {&fused, &single})
      list->push_back({Tensor::from_host(be, s, param), Tensor::from_host(be, s, grad),
                       Tensor::from_host(be, s, m), Tensor::from_host(be, s, v)});
  }
  AdamParams p;
  p.lr = 1e-2f;
  p.weight_decay = 1e-3f;
  for (int64_t step = 1; step <= 3; ++step) {
    p.step = step;
    ops::adam_step_all(fused, p);
    for (const auto& t : single) ops::adam_step(t.param, t.grad, t.m, t.v, p);
  }
  for (size_t k = 0; k < sizes.size(); ++k) {
    EXPECT_EQ(fused[k].param.to_host(), single[k].param.to_host()) << "parameter " << k;
    EXPECT_EQ(fused[k].m.to_host(), single[k].m.to_host()) << "m " << k;
    EXPECT_EQ(fused[k].v.to_host(), single[k].v.to_host()) << "v " << k;
  }
}

}  // namespace
}  // namespace facetool::testing
