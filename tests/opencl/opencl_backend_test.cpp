// The opencl module through the registry: listing, device selection, plugin kernels, NaN.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "backends/opencl/opencl_backend.h"
#include "core/backend/registry.h"
#include "core/ops/ops.h"
#include "tests/opencl/opencl_test_support.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

using testing::all_close;

TEST(OpenclModule, ListsItsDevices) {
  FACETOOL_REQUIRE_OPENCL();
  bool found = false;
  for (const BackendInfo& info : list_backends()) {
    if (info.name != "opencl") continue;
    found = true;
    ASSERT_TRUE(info.available) << info.reason;
    ASSERT_FALSE(info.devices.empty());
    EXPECT_EQ(info.devices[0].rfind("0: ", 0), 0u) << info.devices[0];
    EXPECT_NE(info.devices[0].find("compute units"), std::string::npos) << info.devices[0];
  }
  EXPECT_TRUE(found) << "list_backends() does not mention opencl";
}

TEST(OpenclModule, SelectsDeviceByIndexAndByNamePart) {
  FACETOOL_REQUIRE_OPENCL();
  const auto devices = opencl::enumerate_devices();
  Backend& by_index = get_backend("opencl:0");
  EXPECT_EQ(by_index.name(), "opencl");
  EXPECT_EQ(by_index.device_description(), devices[0].describe());
  // A middle part of the name, in the other case, picks the same device.
  std::string part = devices[0].name.substr(devices[0].name.size() / 3, 4);
  std::transform(part.begin(), part.end(), part.begin(), [](unsigned char c) {
    return static_cast<char>(std::isupper(c) ? std::tolower(c) : std::toupper(c));
  });
  const opencl::DeviceEntry chosen = opencl::select_device(part);
  EXPECT_EQ(chosen.describe(), devices[0].describe()) << "part '" << part << "'";
  EXPECT_EQ(get_backend("opencl").device_description(), devices[0].describe());
}

TEST(OpenclModule, UnknownDeviceGivesAClearError) {
  FACETOOL_REQUIRE_OPENCL();
  try {
    get_backend("opencl:no-such-device-xyz");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("no OpenCL device matches 'no-such-device-xyz'"), std::string::npos)
        << message;
    EXPECT_NE(message.find("0: "), std::string::npos) << "should list the devices: " << message;
  }
  try {
    get_backend("opencl:99");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
}

const char* kAxpbSource = R"CL(
__kernel void axpb(__global const float* x, __global float* y, float a, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] = a * x[i] + (float)OFFSET;
}
)CL";

TEST(OpenclModule, LaunchesPluginKernelsWithBuildOptions) {
  FACETOOL_REQUIRE_OPENCL();
  Backend& be = get_backend("opencl");
  CustomKernel kernel;
  kernel.name = "opencl_test_axpb";
  kernel.opencl_source = kAxpbSource;
  kernel.build_options = "-DOFFSET=3";
  const int n = 1000;  // not a multiple of any work-group size
  Tensor x = testing::random_tensor(be, Shape{n}, 7);
  Tensor y = Tensor::zeros(be, Shape{n});
  ops::launch(kernel, "axpb", n, {KernelArg::of(x), KernelArg::of(y), KernelArg::of(2.0f),
                                  KernelArg::of(int32_t{n})});
  std::vector<float> expected = x.to_host();
  for (float& v : expected) v = 2.0f * v + 3.0f;
  EXPECT_TRUE(all_close(y.to_host(), expected, 1e-6, 1e-6));
}

TEST(OpenclModule, BrokenKernelReportsBuildLogAndProgramName) {
  FACETOOL_REQUIRE_OPENCL();
  Backend& be = get_backend("opencl");
  CustomKernel kernel;
  kernel.name = "deliberately_broken_program";
  kernel.opencl_source =
      "__kernel void broken(__global float* y) { y[0] = undefined_identifier_xyz; }\n";
  Tensor y = Tensor::zeros(be, Shape{4});
  try {
    ops::launch(kernel, "broken", 1, {KernelArg::of(y)});
    be.synchronize();
    FAIL() << "expected a build error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("deliberately_broken_program"), std::string::npos) << message;
    EXPECT_NE(message.find("undefined_identifier_xyz"), std::string::npos)
        << "the compiler's complaint is missing: " << message;
    EXPECT_NE(message.find("Build log"), std::string::npos) << message;
  }
}

TEST(OpenclModule, WrongArgumentCountIsAnError) {
  FACETOOL_REQUIRE_OPENCL();
  Backend& be = get_backend("opencl");
  CustomKernel kernel;
  kernel.name = "opencl_test_axpb";
  kernel.opencl_source = kAxpbSource;
  kernel.build_options = "-DOFFSET=3";
  Tensor x = Tensor::zeros(be, Shape{4});
  EXPECT_THROW(ops::launch(kernel, "axpb", 4, {KernelArg::of(x)}), Error);
  EXPECT_THROW(ops::launch(kernel, "no_such_entry", 4, {KernelArg::of(x)}), Error);
}

TEST(OpenclModule, NanPropagatesThroughReductions) {
  FACETOOL_REQUIRE_OPENCL();
  Backend& be = get_backend("opencl");
  std::vector<float> values(3 * 5 * 7 * 9, 0.5f);
  values[100] = std::numeric_limits<float>::quiet_NaN();
  Tensor x = Tensor::from_host(be, Shape{3, 5, 7, 9}, values);
  EXPECT_TRUE(std::isnan(ops::sum(x).to_host()[0]));
  EXPECT_TRUE(std::isnan(ops::mean(x).to_host()[0]));
  Tensor pooled = ops::global_avg_pool(x);
  EXPECT_TRUE(std::isnan(pooled.to_host()[(100 / 63)]));
  Tensor gamma = Tensor::full(be, Shape{5}, 1.0f), beta = Tensor::zeros(be, Shape{5});
  Tensor rm = Tensor::zeros(be, Shape{5}), rv = Tensor::full(be, Shape{5}, 1.0f);
  Tensor y = ops::batch_norm(x, gamma, beta, rm, rv, BatchNormParams{});
  EXPECT_TRUE(std::isnan(y.to_host()[100]));
  EXPECT_TRUE(std::isnan(ops::l2_normalize(x).to_host()[100]));
}

TEST(OpenclModule, UsesTunedGemmOnCpuDevices) {
  FACETOOL_REQUIRE_OPENCL();
  opencl::OpenclBackend be(opencl::select_device(""));
  if (be.context().is_cpu() && !std::getenv("FACETOOL_CLBLAST_DEFAULTS")) {
    EXPECT_NE(be.gemm().tuning().find("tuning table"), std::string::npos) << be.gemm().tuning();
  }
  // GEMM sizes that are not multiples of the 128x128x16 tiles.
  const int64_t m = 33, n = 65, k = 31;
  Tensor a = testing::random_tensor(be, Shape{m, k}, 1);
  Tensor b = testing::random_tensor(be, Shape{k, n}, 2);
  Tensor c = Tensor::full(be, Shape{m, n}, std::numeric_limits<float>::quiet_NaN());
  be.gemm().run(false, false, m, n, k, 1.0f, opencl::device_memory(a), 0, k,
                opencl::device_memory(b), 0, n, 0.0f, opencl::device_memory(c), 0, n);
  const auto ha = a.to_host(), hb = b.to_host();
  std::vector<float> expected(m * n, 0.0f);
  for (int64_t i = 0; i < m; ++i)
    for (int64_t j = 0; j < n; ++j) {
      double s = 0;
      for (int64_t p = 0; p < k; ++p) s += double(ha[i * k + p]) * hb[p * n + j];
      expected[i * n + j] = static_cast<float>(s);
    }
  // beta = 0 must not read C (it holds NaN).
  EXPECT_TRUE(all_close(c.to_host(), expected, 1e-5, 1e-5));
}

}  // namespace
}  // namespace facetool
