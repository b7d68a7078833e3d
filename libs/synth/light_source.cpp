// Loading, clamping, rotating and tinting lights.
#include "libs/synth/light_source.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libs/light/environment_map_file.h"
#include "libs/light/light_formats.h"
#include "core/sh/light_clamp.h"
#include "core/sh/sh_basis.h"
#include "core/sh/sh_rotation.h"
#include "core/util/error.h"
#include "core/util/math_constants.h"
#include "core/util/file_checks.h"

namespace facetool {
namespace fs = std::filesystem;

const char* const kBlenderStudioLightsDir = "/usr/share/blender/datafiles/studiolights/world";

namespace {


std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext;
}

// Text files that accompany light collections (blender-data's world folder holds license.txt).
bool is_note_file(const fs::path& path) {
  std::string stem = path.stem().string();
  std::transform(stem.begin(), stem.end(), stem.begin(), ::tolower);
  for (const char* note : {"license", "licence", "readme", "copying", "notice", "credits"})
    if (stem.rfind(note, 0) == 0) return true;
  return false;
}

// Files a light folder contributes: environment maps and SH light text files, not notes.
bool is_light_file(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".txt") return !is_note_file(path);
  return ext == ".hdr" || ext == ".exr";
}

LightSource load_light_file(const fs::path& path) {
  LightSource source;
  source.name = path.filename().string();
  if (lower_extension(path) == ".txt") {
    source.light = read_sh_light_file(path.string());
  } else {
    auto map = std::make_shared<sh::EnvironmentMap>(sh::read_environment_map(path.string()));
    for (size_t i = 0; i < map->rgb.size(); ++i) {
      float& value = map->rgb[i];
      check(std::isfinite(value), "environment map '", path.string(),
            "' holds a NaN or infinite value at pixel (", (i / 3) % map->width, ", ",
            (i / 3) / map->width, "); fix the map or remove it from the lights");
      if (value < 0.0f) value = 0.0f;  // negative radiance: none
    }
    source.light = sh::project_environment_map(*map);
    source.environment = std::move(map);
  }
  source.light = make_light_nonnegative(source.light);
  double total = 0.0;
  for (int c = 0; c < 3; ++c) total += source.light[c * sh::kCoeffCount];
  check(total > 0.0, "light '", path.string(),
        "' is black (no positive radiance); remove it from the lights folder");
  return source;
}

}  // namespace

sh::RgbLight read_sh_light_file(const std::string& path) {
  // One reader for every light text layout, each recognised by its shape (never misread).
  return light::read_light(path).light;
}

sh::RgbLight make_light_nonnegative(const sh::RgbLight& light) {
  sh::RgbLight out = sh::clamp_light_nonnegative(light);
  for (int c = 0; c < 3; ++c) {
    sh::ShCoeffs channel = sh::light_channel(out, c);
    const double lowest = sh::min_radiance(channel);
    if (lowest < 0.0) {
      channel[0] += -lowest / sh::ShConstants::k0 * (1.0 + 1e-9);
      sh::set_light_channel(out, c, channel);
    }
  }
  return out;
}

std::vector<LightSource> load_light_sources(const std::vector<std::string>& paths) {
  std::vector<fs::path> files;
  for (const std::string& given : paths) {
    const fs::path path(given);
    std::error_code error;
    if (fs::is_regular_file(path, error)) {
      files.push_back(path);
      continue;
    }
    if ((fs::exists(path, error) || error) && !fs::is_directory(path, error))
      check_regular_input_file(given, kMaxImageFileBytes, "--lights");  // a pipe, a device
    check(fs::is_directory(path, error), "light folder '", given,
          "' does not exist; pass --lights DIR with .hdr/.exr environment maps or .txt SH lights");
    std::vector<std::string> problems;
    const std::vector<std::string> listed = list_folder_files(
        given, "light folder", [](const std::string& name) { return is_light_file(name); },
        problems);
    check(problems.empty(), "light ", problems.empty() ? "" : problems[0], "; fix or remove it");
    std::vector<fs::path> found(listed.begin(), listed.end());
    files.insert(files.end(), found.begin(), found.end());
  }
  check(!files.empty(), "no light files found",
        paths.empty() ? std::string() : " in '" + paths.front() + "'",
        "; pass --lights DIR with .hdr/.exr environment maps (e.g. CC0 HDRIs from polyhaven.com) "
        "or .txt SH lights, or install Debian's blender-data package (",
        kBlenderStudioLightsDir, ")");
  std::vector<LightSource> sources;
  for (const fs::path& file : files) sources.push_back(load_light_file(file));
  return sources;
}

SampledLight sample_light(Random& random, const std::vector<LightSource>& sources,
                          const LightSampling& sampling) {
  check(!sources.empty(), "sample_light: no light sources");
  SampledLight s;
  s.source = static_cast<int>(random.index(sources.size()));
  const double degree = kPi / 180.0;
  const double yaw = random.uniform(0.0, 2.0 * kPi);
  const double tilt_x = random.uniform(-sampling.max_tilt_deg, sampling.max_tilt_deg) * degree;
  const double tilt_z = random.uniform(-sampling.max_tilt_deg, sampling.max_tilt_deg) * degree;
  if (sampling.rotate)
    s.rotation = rotation_y(static_cast<float>(yaw)) * rotation_x(static_cast<float>(tilt_x)) *
               rotation_z(static_cast<float>(tilt_z));
  Vec3f gain;
  for (int c = 0; c < 3; ++c)
    gain[c] = static_cast<float>(random.uniform(1.0 - sampling.color_jitter, 1.0 + sampling.color_jitter));
  s.gain = gain * (3.0f / (gain.x + gain.y + gain.z));
  s.target_peak = random.uniform(sampling.min_peak, sampling.max_peak);
  sh::Mat3 rotation{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rotation[i][j] = s.rotation.m[i][j];
  s.light = sh::rotate_light(sources[s.source].light, rotation);
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < sh::kCoeffCount; ++i) s.light[c * sh::kCoeffCount + i] *= s.gain[c];
  return s;
}

sh::RgbLight scale_light(const sh::RgbLight& light, double scale) {
  sh::RgbLight out = light;
  for (double& value : out) value *= scale;
  return out;
}

Vec3f environment_radiance(const sh::EnvironmentMap& map, Vec3f d) {
  const double theta = std::acos(std::clamp(static_cast<double>(d.y), -1.0, 1.0));
  const double phi = std::atan2(static_cast<double>(d.x), -static_cast<double>(d.z));
  const double u = phi / (2.0 * kPi) + 0.5, v = theta / kPi;
  const double fx = u * map.width - 0.5, fy = std::clamp(v * map.height - 0.5, 0.0, map.height - 1.0);
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const float tx = static_cast<float>(fx - x0), ty = static_cast<float>(fy - y0);
  auto texel = [&](int x, int y) {
    x = ((x % map.width) + map.width) % map.width;
    y = std::clamp(y, 0, map.height - 1);
    const float* p = &map.rgb[(static_cast<size_t>(y) * map.width + x) * 3];
    return Vec3f{p[0], p[1], p[2]};
  };
  return (texel(x0, y0) * (1 - tx) + texel(x0 + 1, y0) * tx) * (1 - ty) +
         (texel(x0, y0 + 1) * (1 - tx) + texel(x0 + 1, y0 + 1) * tx) * ty;
}

}  // namespace facetool
