// Reading equirectangular environment maps with OpenImageIO (the SH integration is core/sh's).
#include "libs/light/environment_map_file.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <vector>

#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/image_limits.h"

namespace facetool::sh {

EnvironmentMap read_environment_map(const std::string& path) {
  check_regular_input_file(path, kMaxImageFileBytes, "environment map");
  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    fail("environment map '", path, "' cannot be read: ", OIIO::geterror(),
         "; give an equirectangular .hdr or .exr file");
  }
  const OIIO::ImageSpec& spec = input->spec();
  const int channels = spec.nchannels;
  check_image_dimensions(path, spec.width, spec.height, channels, "environment map");
  check(channels == 1 || channels >= 3, "environment map '", path, "' has ", channels,
        " channels; give a grey (1) or RGB(A) (3 or more) image");
  const size_t pixels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  std::vector<float> data(pixels * static_cast<size_t>(channels));
  if (!input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, data.data())) {
    fail("environment map '", path, "' cannot be decoded: ", input->geterror());
  }
  EnvironmentMap map;
  map.width = spec.width;
  map.height = spec.height;
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
