// libFuzzer target: a synth sample's channels and metadata (what the dataset reader and synth's
// resume read from each EXR after OpenImageIO decoded it) are validated with facetool::Error.
// Input: byte 0 and 1 give the width and height (1..8), then text lines "c NAME" add a channel
// and "m KEY VALUE" a metadata entry. The EXR container itself is OpenImageIO's to parse.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "libs/io/layered_image.h"
#include "libs/synth/synth_sample.h"
#include "core/util/error.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  facetool::LayeredImage image;
  image.width = 1 + data[0] % 8;
  image.height = 1 + data[1] % 8;
  std::istringstream lines(std::string(reinterpret_cast<const char*>(data) + 2, size - 2));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.size() < 2 || line[1] != ' ') continue;
    const std::string rest = line.substr(2);
    if (line[0] == 'c') {
      image.channel_names.push_back(rest);
    } else if (line[0] == 'm') {
      const size_t space = rest.find(' ');
      image.metadata.emplace_back(rest.substr(0, space),
                                  space == std::string::npos ? "" : rest.substr(space + 1));
    }
  }
  image.pixels.assign(image.plane_size() * image.channel_names.size(), 0.5f);
  try {
    const facetool::SynthSample s = facetool::synth_sample_from_image(image, "fuzz sample");
    using facetool::fuzz::require;
    require(s.width == image.width && s.height == image.height, "sample size changed");
    require(s.image.size() == 3 * s.plane() && s.albedo.size() == 3 * s.plane() &&
                s.normal.size() == 3 * s.plane() && s.mask.size() == s.plane() &&
                s.visibility.size() == 9 * s.plane() && s.depth.size() == s.plane(),
            "an accepted sample's planes have the wrong sizes");
  } catch (const facetool::Error&) {
  }
  return 0;
}
