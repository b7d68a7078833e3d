// Exact resume needs bit-reproducible cpu gradients: convolution weight gradients (Winograd and
// im2col paths) repeated many times on the thread pool give the same bits every time.
#include <gtest/gtest.h>

#include "core/backend/registry.h"
#include "core/ops/ops.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

TEST(TrainingDeterminism, ConvolutionWeightGradientsAreBitReproducible) {
  Backend& be = get_backend("cpu");
  struct Case {
    int64_t kernel;
    int stride;
  };
  for (const Case c : {Case{3, 1}, Case{3, 2}, Case{7, 1}, Case{1, 1}}) {
    const Tensor x = testing::random_tensor(be, Shape{6, 16, 24, 24}, 1);
    const Tensor w = testing::random_tensor(be, Shape{16, 16, c.kernel, c.kernel}, 2);
    Conv2dParams p;
    p.stride = c.stride;
    const Tensor y = ops::conv2d(x, w, nullptr, p);
    const Tensor dy = testing::random_tensor(be, y.shape(), 3);
    const Tensor dw = Tensor::empty(be, w.shape());
    ops::conv2d_backward(x, w, dy, nullptr, &dw, nullptr, p, false);
    const std::vector<float> first = dw.to_host();
    for (int repeat = 0; repeat < 30; ++repeat) {
      ops::conv2d_backward(x, w, dy, nullptr, &dw, nullptr, p, false);
      ASSERT_EQ(dw.to_host(), first) << "kernel " << c.kernel << " stride " << c.stride
                                     << ", repeat " << repeat;
    }
  }
}

}  // namespace
}  // namespace facetool
