// Test helpers: seeded random tensors, tolerance comparisons and the backends under test.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/backend/registry.h"
#include "core/tensor/tensor.h"

namespace facetool::testing {

// Uniform values in [lo, hi) from a fixed seed, so every run sees the same data.
std::vector<float> random_values(size_t count, unsigned seed, float lo = -1.0f, float hi = 1.0f);
Tensor random_tensor(Backend& backend, const Shape& shape, unsigned seed, float lo = -1.0f,
                     float hi = 1.0f);

// Largest |a - b| / (atol + rtol * |b|) over all elements; <= 1 means "close". NaN in either
// gives +infinity unless both are NaN at the same place.
double max_violation(const std::vector<float>& a, const std::vector<float>& b, double atol,
                     double rtol);
// A gtest assertion result: passes when max_violation <= 1, else names the worst element.
::testing::AssertionResult all_close(const std::vector<float>& actual,
                                     const std::vector<float>& expected, double atol,
                                     double rtol);

// Backends that run on this machine, excluding "cpu" (the reference); the opencl one only when
// its runtime has a device. Set FACETOOL_TEST_BACKENDS=opencl,... to restrict.
std::vector<std::string> non_reference_backends();

}  // namespace facetool::testing
