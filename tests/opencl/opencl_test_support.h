// Shared helpers of the opencl tests: skipping when no OpenCL device exists.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "backends/opencl/opencl_context.h"
#include "core/util/error.h"

namespace facetool::testing {

// Empty when an OpenCL device exists, else the reason (used to GTEST_SKIP).
inline std::string opencl_unavailable_reason() {
  try {
    opencl::enumerate_devices();
    return "";
  } catch (const Error& e) {
    return e.what();
  }
}

#define FACETOOL_REQUIRE_OPENCL()                                                   \
  do {                                                                              \
    const std::string reason = ::facetool::testing::opencl_unavailable_reason();    \
    if (!reason.empty()) GTEST_SKIP() << "no OpenCL device: " << reason;            \
  } while (0)

}  // namespace facetool::testing
