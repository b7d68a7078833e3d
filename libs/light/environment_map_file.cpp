// Reading equirectangular environment maps (libs/io/image_file.h; the SH integration is core/sh's).
#include "libs/light/environment_map_file.h"

#include <cmath>
#include <vector>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/image_limits.h"
#include "libs/io/image_file.h"

namespace facetool::sh {

EnvironmentMap read_environment_map(const std::string& path) {
  check_regular_input_file(path, kMaxImageFileBytes, "environment map");
  protect_input_file(path);
  std::unique_ptr<ImageFileReader> input;
  try {
    input = open_image_file(path, "environment map");
  } catch (const Error& e) {
    fail(e.what(), "; give an equirectangular .hdr or .exr file");
  }
  const ImageFileHeader& spec = input->header();
  const int channels = spec.channels;
  check_image_dimensions(path, spec.width, spec.height, channels, "environment map");
  check(channels == 1 || channels >= 3, "environment map '", path, "' has ", channels,
        " channels; give a grey (1) or RGB(A) (3 or more) image");
  const size_t pixels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  std::vector<float> data(pixels * static_cast<size_t>(channels));
  input->read_floats(data.data());
  EnvironmentMap map;
  map.width = static_cast<int>(spec.width);
  map.height = static_cast<int>(spec.height);
  map.rgb.resize(pixels * 3);
  for (size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c) {
      const float value = data[p * channels + (channels == 1 ? 0 : c)];
      check(std::isfinite(value), "environment map '", path, "' holds a NaN or infinite value ",
            "at pixel (", p % static_cast<size_t>(spec.width), ", ",
            p / static_cast<size_t>(spec.width), ") channel ", c,
            "; fix the file (e.g. clamp it in an image editor) or use another map");
      map.rgb[p * 3 + c] = value;
    }
  return map;
}

RgbLight project_environment_map_file(const std::string& path) {
  return project_environment_map(read_environment_map(path));
}

}  // namespace facetool::sh
