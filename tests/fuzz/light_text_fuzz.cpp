// libFuzzer target: the text light formats (SfSNet's 27 numbers, DPR's 9), and facetool's JSON
// reader given the same text, refuse bad files with facetool::Error and never return a
// non-finite coefficient.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "libs/light/light_formats.h"
#include "core/util/error.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

void parse_and_check(const std::string& text, facetool::light::Format format) {
  try {
    const facetool::light::LightFile file = facetool::light::parse_light(text, format, "fuzz.txt");
    for (double v : file.light)
      facetool::fuzz::require(std::isfinite(v), "a light text accepted a non-finite coefficient");
  } catch (const facetool::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using facetool::light::Format;
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (Format format : {Format::Sfsnet, Format::Dpr, Format::Facetool}) parse_and_check(text, format);
  return 0;
}
