// Test helpers: random data, comparisons, and backend enumeration.
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <limits>
#include <random>
#include <sstream>

#include "core/util/shared_library.h"

namespace facetool::testing {

std::vector<float> random_values(size_t count, unsigned seed, float lo, float hi) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  std::vector<float> values(count);
  for (float& v : values) v = dist(rng);
  return values;
}

Tensor random_tensor(Backend& backend, const Shape& shape, unsigned seed, float lo, float hi) {
  return Tensor::from_host(backend, shape,
                           random_values(static_cast<size_t>(shape.numel()), seed, lo, hi));
}

double max_violation(const std::vector<float>& a, const std::vector<float>& b, double atol,
                     double rtol) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]) || std::isnan(b[i])) {
      if (std::isnan(a[i]) && std::isnan(b[i])) continue;
      return std::numeric_limits<double>::infinity();
    }
    const double v = std::abs(double(a[i]) - double(b[i])) / (atol + rtol * std::abs(double(b[i])));
    if (v > worst) worst = v;
  }
  return worst;
}

::testing::AssertionResult all_close(const std::vector<float>& actual,
                                     const std::vector<float>& expected, double atol,
                                     double rtol) {
  if (actual.size() != expected.size())
    return ::testing::AssertionFailure()
           << "sizes differ: " << actual.size() << " vs " << expected.size();
  size_t worst_i = 0;
  double worst = 0.0;
  for (size_t i = 0; i < actual.size(); ++i) {
    double v = max_violation({actual[i]}, {expected[i]}, atol, rtol);
    if (v > worst) {
      worst = v;
      worst_i = i;
    }
  }
  if (worst <= 1.0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "element " << worst_i << ": " << actual[worst_i] << " vs expected "
         << expected[worst_i] << " (atol " << atol << ", rtol " << rtol << ", "
         << worst << "x over tolerance)";
}

std::vector<std::string> non_reference_backends() {
  std::vector<std::string> wanted;
  if (const char* env = std::getenv("FACETOOL_TEST_BACKENDS")) {
    std::string list = env;
    for (char& c : list)
      if (c == ',') c = ':';
    wanted = split_path_list(list);
  }
  std::vector<std::string> names;
  for (const std::string& name : available_backends()) {
    if (name == "cpu") continue;
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), name) == wanted.end()) continue;
    names.push_back(name);
  }
  return names;
}

}  // namespace facetool::testing
