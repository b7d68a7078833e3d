// Hand-computed checks of the cpu backend: batch norm statistics, a linear layer's rows alike in
// any batch, Adam, bilinear borders, strided padded convolution against nested loops, and
// gradient accumulation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/backend/registry.h"
#include "core/ops/ops.h"
#include "tests/cpu/conv_reference.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

Backend& cpu() { return get_backend("cpu"); }

Tensor host(const Shape& s, const std::vector<float>& v) { return Tensor::from_host(cpu(), s, v); }

TEST(CpuReference, BatchNormTrainEvalAndRunningStatistics) {
  // One channel, values 1, 2, 3, 6: mean 3, biased variance 14/4, unbiased 14/3.
  const Tensor x = host(Shape{2, 1, 1, 2}, {1, 2, 3, 6});
  const Tensor gamma = host(Shape{1}, {2.0f});
  const Tensor beta = host(Shape{1}, {0.5f});
  Tensor running_mean = host(Shape{1}, {0.0f});
  Tensor running_var = host(Shape{1}, {1.0f});
  BatchNormParams train;  // momentum 0.1, eps 1e-5
  ops::BatchNormSaved saved;
  const Tensor y = ops::batch_norm(x, gamma, beta, running_mean, running_var, train, &saved);
  const double invstd = 1.0 / std::sqrt(3.5 + 1e-5);
  std::vector<float> expected;
  for (double v : {1.0, 2.0, 3.0, 6.0}) expected.push_back(float(2.0 * (v - 3.0) * invstd + 0.5));
  EXPECT_TRUE(all_close(y.to_host(), expected, 1e-5, 1e-5));
  EXPECT_TRUE(all_close(saved.mean.to_host(), {3.0f}, 1e-6, 1e-6));
  EXPECT_TRUE(all_close(saved.invstd.to_host(), {float(invstd)}, 1e-6, 1e-5));
  // running = 0.9 * old + 0.1 * batch (unbiased variance for the running variance)
  EXPECT_TRUE(all_close(running_mean.to_host(), {0.3f}, 1e-6, 1e-6));
  EXPECT_TRUE(all_close(running_var.to_host(), {float(0.9 + 0.1 * 14.0 / 3.0)}, 1e-6, 1e-6));

  BatchNormParams eval;
  eval.training = false;
  ops::BatchNormSaved eval_saved;
  const Tensor y_eval = ops::batch_norm(x, gamma, beta, running_mean, running_var, eval, &eval_saved);
  const double eval_invstd = 1.0 / std::sqrt(0.9 + 0.1 * 14.0 / 3.0 + 1e-5);
  expected.clear();
  for (double v : {1.0, 2.0, 3.0, 6.0}) expected.push_back(float(2.0 * (v - 0.3) * eval_invstd + 0.5));
  EXPECT_TRUE(all_close(y_eval.to_host(), expected, 1e-5, 1e-5));
  EXPECT_TRUE(all_close(eval_saved.mean.to_host(), {0.3f}, 1e-6, 1e-6));
  // Eval mode leaves the running statistics alone.
  EXPECT_TRUE(all_close(running_mean.to_host(), {0.3f}, 1e-6, 1e-6));
}

TEST(CpuReference, ALinearLayersRowDoesNotDependOnItsBatch) {
  // The paper network's light head at the shipped size: 27 outputs of 2,048 features.
  const int64_t in = 2048, out = 27, batch = 5;
  std::vector<float> xv(batch * in), wv(out * in), bv(out);
  for (size_t i = 0; i < xv.size(); ++i) xv[i] = std::sin(0.37f * i);
  for (size_t i = 0; i < wv.size(); ++i) wv[i] = 0.01f * std::cos(0.11f * i);
  for (size_t i = 0; i < bv.size(); ++i) bv[i] = 0.1f * i;
  const Tensor w = host(Shape{out, in}, wv), b = host(Shape{out}, bv);
  const std::vector<float> all = ops::linear(host(Shape{batch, in}, xv), w, &b).to_host();
  for (int64_t r = 0; r < batch; ++r) {
    const std::vector<float> row(xv.begin() + r * in, xv.begin() + (r + 1) * in);
    const std::vector<float> alone = ops::linear(host(Shape{1, in}, row), w, &b).to_host();
    double reference_worst = 0;
    for (int64_t o = 0; o < out; ++o) {
      EXPECT_EQ(alone[o], all[r * out + o]) << "row " << r << ", output " << o;  // the same bits
      double exact = bv[o];
      for (int64_t k = 0; k < in; ++k) exact += double(row[k]) * wv[o * in + k];
      reference_worst = std::max(reference_worst, std::abs(exact - alone[o]));
    }
    EXPECT_LT(reference_worst, 1e-4) << "row " << r;  // and right (a double-precision sum)
  }
}

TEST(CpuReference, AdamFirstTwoSteps) {
  const double lr = 0.1, b1 = 0.9, b2 = 0.999, eps = 1e-8, wd = 0.01;
  Tensor param = host(Shape{2}, {1.0f, -2.0f});
  Tensor m = Tensor::zeros(cpu(), Shape{2});
  Tensor v = Tensor::zeros(cpu(), Shape{2});
  const std::vector<std::vector<double>> grads = {{0.5, 0.1}, {-0.25, 0.3}};
  std::vector<double> p_ref = {1.0, -2.0}, m_ref = {0, 0}, v_ref = {0, 0};
  for (int step = 1; step <= 2; ++step) {
    AdamParams ap;
    ap.lr = float(lr);
    ap.weight_decay = float(wd);
    ap.step = step;
    const auto& g = grads[step - 1];
    ops::adam_step(param, host(Shape{2}, {float(g[0]), float(g[1])}), m, v, ap);
    for (int i = 0; i < 2; ++i) {
      const double gi = g[i] + wd * p_ref[i];
      m_ref[i] = b1 * m_ref[i] + (1 - b1) * gi;
      v_ref[i] = b2 * v_ref[i] + (1 - b2) * gi * gi;
      const double m_hat = m_ref[i] / (1 - std::pow(b1, step));
      const double v_hat = v_ref[i] / (1 - std::pow(b2, step));
      p_ref[i] -= lr * m_hat / (std::sqrt(v_hat) + eps);
    }
    EXPECT_TRUE(all_close(param.to_host(), {float(p_ref[0]), float(p_ref[1])}, 1e-6, 1e-5))
        << "after step " << step;
    EXPECT_TRUE(all_close(m.to_host(), {float(m_ref[0]), float(m_ref[1])}, 1e-7, 1e-5));
    EXPECT_TRUE(all_close(v.to_host(), {float(v_ref[0]), float(v_ref[1])}, 1e-9, 1e-5));
  }
}

TEST(CpuReference, BilinearUpsamplingAtTheBorders) {
  // align_corners=False: along each axis [a, b] -> [a, .75a + .25b, .25a + .75b, b].
  const Tensor x = host(Shape{1, 1, 2, 2}, {1, 2, 3, 4});
  const std::vector<float> expected = {1.0f, 1.25f, 1.75f, 2.0f,  //
                                       1.5f, 1.75f, 2.25f, 2.5f,  //
                                       2.5f, 2.75f, 3.25f, 3.5f,  //
                                       3.0f, 3.25f, 3.75f, 4.0f};
  EXPECT_TRUE(all_close(ops::upsample_bilinear2x(x).to_host(), expected, 1e-6, 0));
  // The adjoint: each input collects its weights; the column sums of the 1-D matrix are
  // 1 + .75 + .25 = 2 per input, so a ones gradient gives 4 everywhere.
  Tensor dx = Tensor::empty(cpu(), Shape{1, 1, 2, 2});
  ops::upsample_bilinear2x_backward(Tensor::full(cpu(), Shape{1, 1, 4, 4}, 1.0f), dx, false);
  EXPECT_TRUE(all_close(dx.to_host(), {4, 4, 4, 4}, 1e-6, 0));
}

TEST(CpuReference, StrideTwoPaddedConvolutionAtOddSizes) {
  for (int64_t size : {5, 7}) {
    for (int pad : {1, 0}) {
      const Shape xs{2, 3, size, size}, ws{4, 3, 3, 3};
      const auto xv = random_values(xs.numel(), 1), wv = random_values(ws.numel(), 2),
                 bv = random_values(4, 3);
      Conv2dParams p;
      p.stride = 2;
      p.pad = pad;
      const Tensor y = ops::conv2d(host(xs, xv), host(ws, wv), nullptr, p);
      const int64_t out = (size + 2 * pad - 3) / 2 + 1;
      ASSERT_EQ(y.shape(), (Shape{2, 4, out, out}));
      EXPECT_TRUE(all_close(y.to_host(),
                            conv_reference(xv, xs, wv, ws, {0, 0, 0, 0}, 2, pad, out, out), 1e-5,
                            1e-5))
          << "size " << size << " pad " << pad;
      const Tensor bias = host(Shape{4}, bv);
      const Tensor yb = ops::conv2d(host(xs, xv), host(ws, wv), &bias, p);
      EXPECT_TRUE(all_close(yb.to_host(), conv_reference(xv, xs, wv, ws, bv, 2, pad, out, out),
                            1e-5, 1e-5));
    }
  }
}

TEST(CpuReference, LargerConvolutionMatchesNestedLoops) {
  // Big enough for several pixel blocks and threads: 2 images, 40 channels, 24x24.
  const Shape xs{2, 40, 24, 24}, ws{8, 40, 3, 3};
  const auto xv = random_values(xs.numel(), 4), wv = random_values(ws.numel(), 5),
             bv = random_values(8, 6);
  const Tensor bias = host(Shape{8}, bv);
  const Tensor y = ops::conv2d(host(xs, xv), host(ws, wv), &bias, Conv2dParams{});
  EXPECT_TRUE(all_close(y.to_host(), conv_reference(xv, xs, wv, ws, bv, 1, 1, 24, 24), 1e-4, 1e-4));
}

// Stride-1 "same" convolutions with many input channels compute dx as a convolution with
// flipped, transposed weights; few input channels (and 1x1) use GEMM + col2im. Both paths, with
// and without accumulation, against nested loops, on odd non-square images.
TEST(CpuReference, InputGradientOfSameConvolutionsMatchesNestedLoops) {
  for (int64_t channels : {3, 40})
    for (int64_t k : {1, 3, 5}) {
      const Shape xs{2, channels, 13, 11}, ws{24, channels, k, k};
      const int64_t pad = k / 2;
      const auto wv = random_values(ws.numel(), 7);
      const Shape ys{2, 24, 13, 11};
      const auto dyv = random_values(ys.numel(), 8);
      const Tensor x = host(xs, random_values(xs.numel(), 9));
      const Tensor dx = Tensor::empty(cpu(), xs);
      Conv2dParams p;
      ops::conv2d_backward(x, host(ws, wv), host(ys, dyv), &dx, nullptr, nullptr, p, false);
      const std::vector<float> expected = conv_dx_reference(dyv, xs, wv, ws, pad, 13, 11);
      EXPECT_TRUE(all_close(dx.to_host(), expected, 1e-4, 1e-4))
          << channels << " channels, kernel " << k;
      // Accumulating adds the same gradient on top of what dx holds.
      ops::conv2d_backward(x, host(ws, wv), host(ys, dyv), &dx, nullptr, nullptr, p, true);
      std::vector<float> twice = expected;
      for (float& v : twice) v *= 2.0f;
      EXPECT_TRUE(all_close(dx.to_host(), twice, 2e-4, 1e-4))
          << channels << " channels, kernel " << k << ", accumulate";
    }
}

TEST(CpuReference, AccumulateAddsToExistingGradients) {
  const Tensor x = random_tensor(cpu(), Shape{2, 3, 6, 6}, 1);
  const Tensor w = random_tensor(cpu(), Shape{4, 3, 3, 3}, 2);
  const Tensor dy = random_tensor(cpu(), Shape{2, 4, 3, 3}, 3);
  Conv2dParams p;
  p.stride = 2;
  Tensor dx = Tensor::empty(cpu(), x.shape()), dw = Tensor::empty(cpu(), w.shape()),
         db = Tensor::empty(cpu(), Shape{4});
  ops::conv2d_backward(x, w, dy, &dx, &dw, &db, p, false);
  Tensor dx2 = Tensor::full(cpu(), x.shape(), 0.5f), dw2 = Tensor::full(cpu(), w.shape(), -1.0f),
         db2 = Tensor::full(cpu(), Shape{4}, 2.0f);
  ops::conv2d_backward(x, w, dy, &dx2, &dw2, &db2, p, true);
  auto shifted = [](std::vector<float> v, float by) {
    for (float& f : v) f += by;
    return v;
  };
  EXPECT_TRUE(all_close(dx2.to_host(), shifted(dx.to_host(), 0.5f), 1e-5, 1e-5));
  EXPECT_TRUE(all_close(dw2.to_host(), shifted(dw.to_host(), -1.0f), 1e-5, 1e-5));
  EXPECT_TRUE(all_close(db2.to_host(), shifted(db.to_host(), 2.0f), 1e-5, 1e-5));

  // Element-wise and normalisation backwards accumulate the same way.
  const Tensor a = random_tensor(cpu(), Shape{2, 3, 4, 4}, 4);
  const Tensor g = random_tensor(cpu(), a.shape(), 5);
  Tensor fresh = Tensor::empty(cpu(), a.shape());
  ops::leaky_relu_backward(a, 0.2f, g, fresh, false);
  Tensor acc = Tensor::full(cpu(), a.shape(), 1.0f);
  ops::leaky_relu_backward(a, 0.2f, g, acc, true);
  EXPECT_TRUE(all_close(acc.to_host(), shifted(fresh.to_host(), 1.0f), 1e-6, 1e-6));
  Tensor up_fresh = Tensor::empty(cpu(), Shape{2, 3, 2, 2});
  ops::upsample_bilinear2x_backward(a, up_fresh, false);
  Tensor up_acc = Tensor::full(cpu(), Shape{2, 3, 2, 2}, 3.0f);
  ops::upsample_bilinear2x_backward(a, up_acc, true);
  EXPECT_TRUE(all_close(up_acc.to_host(), shifted(up_fresh.to_host(), 3.0f), 1e-5, 1e-5));
}

TEST(CpuReference, MaskedMseValueAndEmptyMask) {
  // C = 2, one image of 2 pixels; mask (1, 0): loss = ((1-0)^2 + (3-1)^2) / (2 * 1) = 2.5.
  const Tensor pred = host(Shape{1, 2, 1, 2}, {1, 5, 3, 7});
  const Tensor target = host(Shape{1, 2, 1, 2}, {0, 0, 1, 0});
  const Tensor mask = host(Shape{1, 1, 1, 2}, {1, 0});
  EXPECT_TRUE(all_close(ops::masked_mse(pred, target, mask).to_host(), {2.5f}, 1e-6, 1e-6));
  const Tensor empty_mask = host(Shape{1, 1, 1, 2}, {0, 0});
  EXPECT_TRUE(all_close(ops::masked_mse(pred, target, empty_mask).to_host(), {0.0f}, 0, 0));
  Tensor dpred = Tensor::full(cpu(), pred.shape(), 9.0f);
  ops::masked_mse_backward(pred, target, empty_mask, host(Shape{1}, {1.0f}), &dpred, nullptr,
                           false);
  EXPECT_TRUE(all_close(dpred.to_host(), {0, 0, 0, 0}, 0, 0));
}

}  // namespace
}  // namespace facetool::testing
