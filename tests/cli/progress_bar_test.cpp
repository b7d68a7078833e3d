// Tests of the progress line format and of the terminal / log drawing policy.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "core/util/progress_bar.h"

namespace facetool {
namespace {

TEST(ProgressBar, DurationFormat) {
  EXPECT_EQ(format_duration(0), "00:00");
  EXPECT_EQ(format_duration(65), "01:05");
  EXPECT_EQ(format_duration(3599), "59:59");
  EXPECT_EQ(format_duration(3600 + 2 * 60 + 3), "1:02:03");
  EXPECT_EQ(format_duration(-5), "00:00");
}

TEST(ProgressBar, LineShowsBarCountRateAndEta) {
  // 25 of 100 in 5 s: 5 it/s, 75 left -> 15 s.
  EXPECT_EQ(format_progress("train", 25, 100, 5.0, "it", 8),
            "train [##......] 25/100 5.0 it/s ETA 00:15");
  EXPECT_EQ(format_progress("eval", 100, 100, 20.0, "img", 4),
            "eval [####] 100/100 5.0 img/s in 00:20");
  EXPECT_EQ(format_progress("x", 0, 10, 0.0, "it", 2), "x [..] 0/10 0.000 it/s ETA --:--");
  // Unknown total: no bar, no ETA.
  EXPECT_EQ(format_progress("synth", 300, 0, 2.0), "synth 300 150 it/s");
}

TEST(ProgressBar, LogOutputEndsWithTheFinalLine) {
  std::ostringstream out;
  {
    ProgressBar bar("load", 3, "it", out, /*interactive=*/false);
    bar.advance();
    bar.advance(2);
  }  // the destructor finishes
  const std::string text = out.str();
  EXPECT_EQ(text.find('\r'), std::string::npos);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  EXPECT_NE(text.find("load [##############################] 3/3"), std::string::npos) << text;
}

TEST(ProgressBar, TerminalOutputRedrawsInPlace) {
  std::ostringstream out;
  ProgressBar bar("load", 2, "it", out, /*interactive=*/true);
  bar.update(2);
  bar.finish();
  bar.finish();  // a second finish prints nothing
  const std::string text = out.str();
  EXPECT_EQ(text.front(), '\r');
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
  EXPECT_NE(text.rfind("\rload [##############################] 2/2"), std::string::npos);
}

}  // namespace
}  // namespace facetool
