// CropFraming: presets, the recorded text round trip, its mapping, and clear errors.
#include <gtest/gtest.h>

#include "core/util/error.h"
#include "libs/image/crop_framing.h"

namespace facetool {
namespace {

TEST(CropFraming, TextRoundTripsAndPresetsParse) {
  for (const CropFraming& f : {v1_framing(), v2_framing()}) {
    EXPECT_EQ(parse_framing(framing_text(f), "test"), f) << framing_text(f);
  }
  EXPECT_EQ(parse_framing("v1", "test"), CropFraming{});
  EXPECT_EQ(parse_framing("v2", "test"), v2_framing());
  EXPECT_EQ(framing_text(v1_framing()), "zoom 1 centre 0.5 0.5 border edge-repeat");
  EXPECT_EQ(framing_text(v2_framing()), "zoom 1.6 centre 0.5 0.456 border ring-mean");
  CropFraming third;
  third.zoom = 1.0 / 3.0;
  EXPECT_EQ(parse_framing(framing_text(third), "test").zoom, third.zoom);
  const CropFraming odd = parse_framing("zoom 1.25 centre 0.4 0.6 border ring-mean", "test");
  EXPECT_EQ(odd.zoom, 1.25);
  EXPECT_EQ(odd.border, BorderFill::kRingMean);
}

TEST(CropFraming, MapsV1UnitsAboutItsCentre) {
  const CropFraming f = v2_framing();
  EXPECT_DOUBLE_EQ(f.to_x(f.centre_x), 0.5);
  EXPECT_DOUBLE_EQ(f.to_y(f.centre_y), 0.5);
  // Distances grow by the zoom.
  EXPECT_NEAR(f.to_y(0.677) - f.to_y(0.235), f.zoom * (0.677 - 0.235), 1e-12);
  const CropFraming v1;
  EXPECT_DOUBLE_EQ(v1.to_x(0.3), 0.3);
}

TEST(CropFraming, BadTextIsRefusedWithTheThingNamed) {
  for (const char* bad : {"v3", "zoom 1 centre 0.5", "zoom x centre 0.5 0.5 border ring-mean",
                          "zoom 100 centre 0.5 0.5 border ring-mean", "zoom 1 centre 2 0.5 border ring-mean",
                          "zoom 1 centre 0.5 0.5 border streaks", "zoom 1 centre 0.5 0.5 border ring-mean extra"}) {
    try {
      parse_framing(bad, "metadata 'framing'");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("metadata 'framing'"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace facetool
