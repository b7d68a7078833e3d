// The grey-input augmentation: which rows turn grey, what their channels become, the config key.
#include <gtest/gtest.h>

#include <cmath>

#include "core/backend/registry.h"
#include "core/util/error.h"
#include "libs/train/grey_inputs.h"
#include "libs/train/training_config.h"
#include "tests/support/test_support.h"

namespace facetool {
namespace {

Backend& cpu() { return get_backend("cpu"); }

// Every row grey: RGB become the Rec. 709 luminance of the row's own colour, computed here pixel
// by pixel; the prior channels (3 to 5) and a fraction of 0 leave everything as it was.
TEST(GreyInputs, GreyRowsHoldTheLuminanceAndKeepThePrior) {
  const Shape shape{3, 6, 5, 7};
  const Tensor input = testing::random_tensor(cpu(), shape, 11, 0.0f, 1.0f);
  const std::vector<float> before = input.to_host();
  EXPECT_EQ(grey_some_rows(input, 1, 0, 0, 0.0).to_host(), before);
  const std::vector<float> after = grey_some_rows(input, 1, 0, 0, 1.0).to_host();
  const size_t plane = 5 * 7;
  for (size_t n = 0; n < 3; ++n)
    for (size_t p = 0; p < plane; ++p) {
      const size_t at = n * 6 * plane + p;
      const double y = 0.2126 * before[at] + 0.7152 * before[at + plane] + 0.0722 * before[at + 2 * plane];
      for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(after[at + c * plane], y, 1e-6) << n << " " << c;
      for (size_t c = 3; c < 6; ++c) EXPECT_EQ(after[at + c * plane], before[at + c * plane]);
    }
  // A slice of the batch starting at row `first_row` greys the rows the whole batch would.
  for (int64_t first_row : {0, 5, 17}) {
    const std::vector<float> half = grey_some_rows(input, 1, 3, 0, 0.5, first_row).to_host();
    for (int64_t n = 0; n < 3; ++n) {
      const size_t at = static_cast<size_t>(n) * 6 * plane;
      const bool changed = half[at] != before[at] || half[at + plane] != before[at + plane];
      EXPECT_EQ(changed, grey_row(1, 3, 0, first_row + n, 0.5)) << first_row << " " << n;
    }
  }
}

// A fraction of 0.25 greys about a quarter of the rows (1,600 draws: within 0.05, over 6 standard
// deviations), the same rows for the same (seed, step, source), other rows at another step.
TEST(GreyInputs, TheFractionHoldsAndTheChoiceIsReproducible) {
  int grey = 0, total = 0, differ = 0;
  for (int64_t step = 0; step < 40; ++step)
    for (int source = 0; source < 2; ++source)
      for (int64_t row = 0; row < 20; ++row) {
        const bool g = grey_row(7, step, source, row, 0.25);
        EXPECT_EQ(g, grey_row(7, step, source, row, 0.25));
        differ += g != grey_row(7, step + 1000, source, row, 0.25);
        grey += g;
        ++total;
      }
  EXPECT_NEAR(static_cast<double>(grey) / total, 0.25, 0.05);
  EXPECT_GT(differ, total / 5);
  EXPECT_FALSE(grey_row(7, 0, 0, 0, 0.0));
  EXPECT_TRUE(grey_row(7, 0, 0, 0, 1.0));
}

TEST(GreyInputs, TheSourceKeyIsReadAndChecked) {
  const std::string head = R"({"name": "x", "steps": 1, "sources": [{"name": "s", "directory": "d", )";
  const std::string tail = R"("terms": {"albedo": 1}}]})";
  EXPECT_EQ(parse_training_config(head + tail, "a.json").sources[0].grey_fraction, 0.0);
  EXPECT_EQ(parse_training_config(head + R"("grey_fraction": 0.3, )" + tail, "a.json").sources[0].grey_fraction, 0.3);
  try {
    parse_training_config(head + R"("grey_fraction": 1.5, )" + tail, "b.json");
    ADD_FAILURE() << "grey_fraction 1.5 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("grey_fraction"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("b.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace facetool
