// Environment-map files (HDR/EXR, read with OpenImageIO) as panoramas and as 27 SH coefficients.
#pragma once

#include <string>

#include "core/sh/envmap_projection.h"

namespace facetool::sh {

// Reads an image OpenImageIO understands (Radiance .hdr, OpenEXR, ...). One channel is used as
// grey; with three or more the first three are R, G, B (alpha is ignored). Throws
// facetool::Error naming the file when it cannot be read or has two channels.
EnvironmentMap read_environment_map(const std::string& path);

// read_environment_map, then project_environment_map.
RgbLight project_environment_map_file(const std::string& path);

}  // namespace facetool::sh
