// libFuzzer target: facetool's light JSON reader refuses any malformed file with facetool::Error
// and never returns a light holding a non-finite coefficient.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "libs/light/light_formats.h"
#include "core/util/error.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const facetool::light::LightFile file =
        facetool::light::parse_light(text, facetool::light::Format::Facetool, "fuzz.json");
    for (double v : file.light)
      facetool::fuzz::require(std::isfinite(v), "light JSON accepted a non-finite coefficient");
  } catch (const facetool::Error&) {
  }
  return 0;
}
