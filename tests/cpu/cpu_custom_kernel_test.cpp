// Custom kernel launches on the cpu backend: chunked execution and missing CPU entries.
#include <gtest/gtest.h>

#include "core/backend/registry.h"
#include "core/ops/ops.h"
#include "core/util/error.h"
#include "tests/support/test_support.h"

namespace facetool::testing {
namespace {

// y[i] = a * x[i] + b; arguments: x, y, a (float), b (float).
void affine(const CpuKernelArgs& args, int64_t begin, int64_t end) {
  const float* x = args.tensor(0);
  float* y = args.tensor(1);
  const float a = args.float_arg(2), b = args.float_arg(3);
  for (int64_t i = begin; i < end; ++i) y[i] = a * x[i] + b;
}

CustomKernel affine_kernel() {
  CustomKernel k;
  k.name = "test_affine";
  k.opencl_source = "__kernel void affine(__global const float* x, __global float* y, float a, "
                    "float b) { int i = get_global_id(0); y[i] = a * x[i] + b; }";
  k.cpu_entries["affine"] = affine;
  return k;
}

TEST(CpuCustomKernel, RunsEveryItemAcrossChunks) {
  Backend& cpu = get_backend("cpu");
  const int64_t items = 100003;  // not a multiple of any chunk size
  const std::vector<float> xv = random_values(items, 7);
  const Tensor x = Tensor::from_host(cpu, Shape{items}, xv);
  const Tensor y = Tensor::full(cpu, Shape{items}, -99.0f);
  ops::launch(affine_kernel(), "affine", items,
              {KernelArg::of(x), KernelArg::of(y), KernelArg::of(2.0f), KernelArg::of(-0.5f)});
  std::vector<float> expected(items);
  for (int64_t i = 0; i < items; ++i) expected[i] = 2.0f * xv[i] - 0.5f;
  EXPECT_TRUE(all_close(y.to_host(), expected, 0, 0));
}

TEST(CpuCustomKernel, MissingCpuEntryIsAClearError) {
  Backend& cpu = get_backend("cpu");
  const Tensor x = Tensor::zeros(cpu, Shape{4});
  try {
    ops::launch(affine_kernel(), "shade", 4, {KernelArg::of(x)});
    FAIL() << "expected a facetool::Error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("test_affine"), std::string::npos) << message;
    EXPECT_NE(message.find("shade"), std::string::npos) << message;
    EXPECT_NE(message.find("affine"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace facetool::testing
