// The messages behind the fuzzers' findings: each damaged input is refused with a facetool::Error
// that names the file and the field (the replays only check that nothing else escapes).
#include <gtest/gtest.h>

#include <string>

#include "libs/io/layered_image.h"
#include "libs/light/light_formats.h"
#include "libs/synth/synth_sample.h"
#include "core/util/error.h"

namespace facetool {
namespace {

// The message of the facetool::Error that `action` throws ("" if it throws none).
template <typename Action>
std::string error_of(Action action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string light_json_error(const std::string& text) {
  return error_of([&] { light::parse_light(text, light::Format::Facetool, "L.json"); });
}

TEST(ParserErrors, LightJsonMembersOfTheWrongTypeNameTheFileAndMember) {
  EXPECT_NE(light_json_error(R"({"format": 1, "version": 1})").find("'L.json' is not a facetool light"),
            std::string::npos);
  const std::string version = light_json_error(R"({"format": "facetool-light", "version": "1"})");
  EXPECT_NE(version.find("'L.json' has version \"1\""), std::string::npos) << version;
  const std::string missing = light_json_error(R"({"format": "facetool-light", "version": 1})");
  EXPECT_NE(missing.find("'L.json' has no \"coefficients\""), std::string::npos) << missing;
  const std::string array =
      light_json_error(R"({"format": "facetool-light", "version": 1, "coefficients": [1]})");
  EXPECT_NE(array.find("'L.json' has no \"coefficients\""), std::string::npos) << array;
}

TEST(ParserErrors, AValidLightJsonStillReads) {
  const light::LightFile file = light::parse_light(
      R"({"format": "facetool-light", "version": 1, "coefficients": {"r": [1,2,3,4,5,6,7,8,9],
          "g": [0,0,0,0,0,0,0,0,0], "b": [0,0,0,0,0,0,0,0,-1.5]}})",
      light::Format::Facetool, "L.json");
  EXPECT_EQ(file.light[0], 1.0);
  EXPECT_EQ(file.light[8], 9.0);
  EXPECT_EQ(file.light[26], -1.5);
}

// A complete sample's metadata (what synth writes), with `field` replaced by `value`.
LayeredImage sample_with(const std::string& field, const std::string& value) {
  SynthSample s;
  s.width = s.height = 2;
  s.image.assign(3 * s.plane(), 0.f);
  s.albedo = s.normal = s.image;
  s.mask.assign(s.plane(), 1.f);
  s.depth = s.mask;
  s.visibility.assign(9 * s.plane(), 0.f);
  s.run_seed = 7;
  s.index = 3;
  LayeredImage image = synth_sample_to_image(s);
  image.set_metadata("facetool:" + field, value);
  return image;
}

TEST(ParserErrors, DamagedSampleIntegersNameTheSampleAndField) {
  EXPECT_EQ(synth_sample_from_image(sample_with("seed", "7"), "S.exr").run_seed, 7u);
  for (const char* field : {"seed", "sample_seed", "sample_index"}) {
    for (const char* value : {"", "x", "12x", "99999999999999999999999", " 1"}) {
      const std::string message =
          error_of([&] { synth_sample_from_image(sample_with(field, value), "S.exr"); });
      EXPECT_NE(message.find("sample 'S.exr': metadata " + std::string(field)), std::string::npos)
          << field << "='" << value << "': " << message;
    }
  }
  EXPECT_NE(error_of([&] { synth_sample_from_image(sample_with("seed", "-1"), "S.exr"); })
                .find("non-negative"),
            std::string::npos);
  EXPECT_EQ(synth_sample_from_image(sample_with("sample_index", "-2"), "S.exr").index, -2);
}

}  // namespace
}  // namespace facetool
