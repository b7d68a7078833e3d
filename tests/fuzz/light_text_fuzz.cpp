// libFuzzer target: the text light formats (SfSNet's 27 numbers, DPR's 9), guessed and forced,
// and facetool's JSON reader forced onto text, refuse bad files with facetool::Error and never
// return a non-finite coefficient.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/light/light_formats.h"
#include "core/util/error.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

void read_and_check(const std::string& path, const facetool::light::Format* format) {
  try {
    const facetool::light::LightFile file = facetool::light::read_light(path, format);
    for (double v : file.light)
      facetool::fuzz::require(std::isfinite(v), "a light text accepted a non-finite coefficient");
  } catch (const facetool::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using facetool::light::Format;
  static const std::string path = facetool::fuzz::scratch_path("light.txt");
  facetool::fuzz::write_file(path, data, size);
  read_and_check(path, nullptr);  // guessed from the count of numbers
  for (Format format : {Format::Sfsnet, Format::Dpr, Format::Facetool}) read_and_check(path, &format);
  return 0;
}
