// Light sources for the generator: environment maps (HDR/EXR) and SH light files, projected to
// 27 SH coefficients and made non-negative; random rotation, colour jitter.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/sh/envmap_projection.h"
#include "core/sh/sh_types.h"
#include "libs/synth/random.h"
#include "libs/synth/vec3.h"

namespace facetool {

struct LightSource {
  std::string name;   // file name, for the manifest and metadata
  sh::RgbLight light; // non-negative on the sphere (checked at 64,000 directions)
  // The panorama, for background views; null for SH light files.
  std::shared_ptr<const sh::EnvironmentMap> environment;
};

// Where Debian's blender-data package puts its 8 CC0 world HDRIs.
extern const char* const kBlenderStudioLightsDir;

// Loads every *.hdr, *.exr (environment maps) and *.txt (SH light) file of each directory (or
// the file itself), sorted by path. Throws facetool::Error naming the file that cannot be read,
// or saying where to find lights when none are found.
std::vector<LightSource> load_light_sources(const std::vector<std::string>& paths);

// An SH light text file in any layout libs/light/light_formats.h recognises by its shape:
// 9 rows of "R G B" (row i holding coefficient i, sh_basis.h order, of each channel), SfSNet's
// 3 rows of 9 (converted), DPR's 9 numbers; whitespace or commas, '#' comments. Any other
// layout, including 27 numbers on one line, is refused with the file's name.
sh::RgbLight read_sh_light_file(const std::string& path);

// Projection of max(0, L) once more when L dips below zero anywhere, then (if rounding leaves a
// dip) a raise of the constant term just large enough: the result is >= 0 at all 64,000
// Fibonacci directions.
sh::RgbLight make_light_nonnegative(const sh::RgbLight& light);

struct LightSampling {
  bool rotate = true;        // false: keep the lights as loaded (tests)
  double max_tilt_deg = 20;  // besides a full turn about +Y, tilt about X and Z up to this
  double color_jitter = 0.1; // per-channel gain in [1 - j, 1 + j], normalised to mean 1
  double min_peak = 0.8, max_peak = 1.0;  // brightest face pixel after scaling (paper)
};

// One random light: which source, how it is turned and tinted. light = tinted, rotated source
// light before the intensity scale (which depends on the rendered face).
struct SampledLight {
  int source = 0;
  Mat3f rotation;           // light from direction w now arrives from rotation * w
  Vec3f gain{1, 1, 1};
  double target_peak = 1.0;
  sh::RgbLight light{};
};
SampledLight sample_light(Random& random, const std::vector<LightSource>& sources,
                          const LightSampling& sampling);

// Multiplies every coefficient of the light by `scale`.
sh::RgbLight scale_light(const sh::RgbLight& light, double scale);

// Bilinear lookup of a panorama's radiance arriving from unit direction d (sh::equirect_direction
// conventions), wrapping around horizontally.
Vec3f environment_radiance(const sh::EnvironmentMap& map, Vec3f d);

}  // namespace facetool
