// Parity: each op x backend x geometry is one value-parameterised test against the cpu backend.
#include <gtest/gtest.h>

#include <tuple>

#include "core/backend/registry.h"
#include "tests/parity/parity_cases.h"
#include "tests/support/test_support.h"

namespace facetool::parity {
namespace {

// Placeholder parameter when no backend besides cpu can run here.
const char* kNoBackend = "none";

std::vector<std::string> backends_under_test() {
  std::vector<std::string> names = testing::non_reference_backends();
  if (names.empty()) names.push_back(kNoBackend);
  return names;
}

using Param = std::tuple<size_t, std::string, size_t>;  // case index, backend, geometry index

class Parity : public ::testing::TestWithParam<Param> {};

TEST_P(Parity, MatchesCpu) {
  const auto& [case_index, backend_name, geometry_index] = GetParam();
  if (backend_name == kNoBackend)
    GTEST_SKIP() << "no non-reference backend available (is an OpenCL ICD such as "
                    "pocl-opencl-icd installed and facetool_backend_opencl.so built?)";
  const OpCase& op = op_cases()[case_index];
  const Geometry& g = geometries()[geometry_index];
  const std::optional<Outputs> expected = op.run(get_backend("cpu"), g);
  if (!expected) GTEST_SKIP() << op.name << " does not apply to geometry " << g.label();
  const std::optional<Outputs> actual = op.run(get_backend(backend_name), g);
  ASSERT_TRUE(actual.has_value());
  ASSERT_EQ(actual->size(), expected->size());
  for (size_t i = 0; i < expected->size(); ++i) {
    ASSERT_EQ((*actual)[i].first, (*expected)[i].first);
    EXPECT_TRUE(testing::all_close((*actual)[i].second, (*expected)[i].second, op.atol, op.rtol))
        << op.name << " output '" << (*expected)[i].first << "' on " << backend_name << " at "
        << g.label();
  }
}

std::string param_name(const ::testing::TestParamInfo<Param>& info) {
  const auto& [case_index, backend_name, geometry_index] = info.param;
  std::string name = op_cases()[case_index].name + "_" + backend_name + "_" +
                     geometries()[geometry_index].label();
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

std::vector<size_t> indices(size_t count) {
  std::vector<size_t> v(count);
  for (size_t i = 0; i < count; ++i) v[i] = i;
  return v;
}

INSTANTIATE_TEST_SUITE_P(AllOps, Parity,
                         ::testing::Combine(::testing::ValuesIn(indices(op_cases().size())),
                                            ::testing::ValuesIn(backends_under_test()),
                                            ::testing::ValuesIn(indices(geometries().size()))),
                         param_name);

}  // namespace
}  // namespace facetool::parity
