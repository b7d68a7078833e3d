// ProgramCache: memory and disk hits, corrupt cache files, and build errors with the log.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "backends/opencl/program_cache.h"
#include "tests/opencl/opencl_test_support.h"

namespace facetool {
namespace {

namespace fs = std::filesystem;

// A fresh cache folder per test, removed afterwards.
class ProgramCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    FACETOOL_REQUIRE_OPENCL();
    dir_ = fs::temp_directory_path() /
           ("facetool_program_cache_test_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
    context_ = std::make_unique<opencl::Context>(opencl::select_device(""));
  }
  void TearDown() override {
    context_.reset();
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }
  fs::path dir_;
  std::unique_ptr<opencl::Context> context_;
};

const char* kSource =
    "__kernel void twice(__global float* y, int n) {\n"
    "  int i = get_global_id(0); if (i < n) y[i] *= 2.0f; }\n";

TEST_F(ProgramCacheTest, SecondBuildIsAHitInMemoryAndOnDisk) {
  {
    opencl::ProgramCache cache(*context_, dir_.string());
    cl_program first = cache.get("twice", kSource, "");
    cl_program second = cache.get("twice", kSource, "");
    EXPECT_EQ(first, second);
    EXPECT_EQ(cache.stats().compiles, 1);
    EXPECT_EQ(cache.stats().memory_hits, 1);
    EXPECT_TRUE(fs::exists(cache.cache_file(kSource, ""))) << cache.cache_file(kSource, "");
    // Other options are another program.
    cache.get("twice", kSource, "-DUNUSED=1");
    EXPECT_EQ(cache.stats().compiles, 2);
  }
  opencl::ProgramCache fresh(*context_, dir_.string());
  cl_program loaded = fresh.get("twice", kSource, "");
  EXPECT_EQ(fresh.stats().disk_hits, 1);
  EXPECT_EQ(fresh.stats().compiles, 0);
  cl_int status = CL_SUCCESS;
  cl_kernel kernel = clCreateKernel(loaded, "twice", &status);
  EXPECT_EQ(status, CL_SUCCESS) << opencl::error_string(status);
  if (kernel) clReleaseKernel(kernel);
}

TEST_F(ProgramCacheTest, CorruptCacheFileFallsBackToSource) {
  std::string path;
  {
    opencl::ProgramCache cache(*context_, dir_.string());
    cache.get("twice", kSource, "");
    path = cache.cache_file(kSource, "");
  }
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << "this is not a program binary";
  }
  opencl::ProgramCache cache(*context_, dir_.string());
  cl_program program = cache.get("twice", kSource, "");
  EXPECT_NE(program, nullptr);
  EXPECT_EQ(cache.stats().compiles, 1);
  EXPECT_EQ(cache.stats().disk_hits, 0);
}

TEST_F(ProgramCacheTest, BuildFailureCarriesLogAndName) {
  opencl::ProgramCache cache(*context_, dir_.string());
  try {
    cache.get("my_broken_program", "__kernel void f() { int x = ; }", "");
    FAIL() << "expected a build error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("my_broken_program"), std::string::npos) << message;
    EXPECT_NE(message.find("error"), std::string::npos) << "no compiler log: " << message;
  }
  // Nothing is cached for a failed build.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 0);
}

TEST_F(ProgramCacheTest, NoDirectoryMeansMemoryOnly) {
  opencl::ProgramCache cache(*context_, "");
  cache.get("twice", kSource, "");
  cache.get("twice", kSource, "");
  EXPECT_EQ(cache.stats().compiles, 1);
  EXPECT_EQ(cache.stats().memory_hits, 1);
  EXPECT_EQ(cache.cache_file(kSource, ""), "");
}

}  // namespace
}  // namespace facetool
