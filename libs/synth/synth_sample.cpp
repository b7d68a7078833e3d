// SynthSample <-> EXR channels and metadata.
#include "libs/synth/synth_sample.h"

#include <charconv>
#include <cstdio>
#include <sstream>
#include <type_traits>

#include "libs/io/exr_io.h"
#include "core/util/error.h"

namespace facetool {

const char* const kSynthGeneratorVersion = "facetool-synth-2";

namespace {

const char kPrefix[] = "facetool:";

std::string key(const char* name) { return std::string(kPrefix) + name; }

std::string format_numbers(const double* values, size_t count) {
  std::string out;
  char buffer[40];
  for (size_t k = 0; k < count; ++k) {
    std::snprintf(buffer, sizeof(buffer), "%.17g", values[k]);
    if (k) out += ' ';
    out += buffer;
  }
  return out;
}

std::vector<double> parse_numbers(const std::string& text, size_t expected, const std::string& what,
                                  const std::string& source) {
  std::istringstream in(text);
  std::vector<double> values;
  double value;
  while (in >> value) values.push_back(value);
  check(values.size() == expected && in.eof(), "sample '", source, "': metadata ", what,
        " should hold ", expected, " numbers: '", text, "'");
  return values;
}

// A whole decimal integer (no sign for unsigned fields, nothing after it) or a facetool::Error.
template <typename Integer>
Integer parse_integer(const std::string& text, const char* what, const std::string& source) {
  Integer value = 0;
  const char* end = text.data() + text.size();
  const auto [after, status] = std::from_chars(text.data(), end, value);
  check(!text.empty() && status == std::errc() && after == end, "sample '", source,
        "': metadata ", what, " should hold one ", std::is_signed_v<Integer> ? "" : "non-negative ",
        "integer: '", text, "' (a damaged sample: remove it and regenerate)");
  return value;
}

const std::string& require(const LayeredImage& image, const char* name, const std::string& source) {
  const std::string* value = image.find_metadata(key(name));
  check(value != nullptr, "'", source, "' has no ", key(name),
        " metadata: it is not a facetool synth sample");
  return *value;
}

struct ChannelGroup {
  std::vector<float> SynthSample::*member;
  std::vector<std::string> names;
};

const std::vector<ChannelGroup>& channel_groups() {
  static const std::vector<ChannelGroup> groups = {
      {&SynthSample::image, {"R", "G", "B"}},
      {&SynthSample::albedo, {"albedo.R", "albedo.G", "albedo.B"}},
      {&SynthSample::normal, {"normal.X", "normal.Y", "normal.Z"}},
      {&SynthSample::mask, {"mask"}},
      {&SynthSample::visibility,
       {"visibility.0", "visibility.1", "visibility.2", "visibility.3", "visibility.4",
        "visibility.5", "visibility.6", "visibility.7", "visibility.8"}},
      {&SynthSample::depth, {"depth.Z"}},
  };
  return groups;
}

// Fills the common fields of `info`-like metadata from `image`.
void read_info(const LayeredImage& image, const std::string& source, SynthSampleInfo& info) {
  info.generator_version = require(image, "generator_version", source);
  info.run_seed = parse_integer<uint64_t>(require(image, "seed", source), "seed", source);
  info.sample_seed =
      parse_integer<uint64_t>(require(image, "sample_seed", source), "sample_seed", source);
  info.index = parse_integer<int64_t>(require(image, "sample_index", source), "sample_index", source);
  if (const std::string* settings = image.find_metadata(key("settings"))) info.settings = *settings;
  const auto pose = parse_numbers(require(image, "pose_deg", source), 3, "pose_deg", source);
  info.pose = {pose[0], pose[1], pose[2]};
  info.fov_deg = parse_numbers(require(image, "fov_deg", source), 1, "fov_deg", source)[0];
  info.light_source = require(image, "light_source", source);
  info.width = image.width;
  info.height = image.height;
}

}  // namespace

LayeredImage synth_sample_to_image(const SynthSample& s) {
  std::vector<std::string> names;
  for (const ChannelGroup& group : channel_groups())
    names.insert(names.end(), group.names.begin(), group.names.end());
  LayeredImage image(s.width, s.height, names);
  int channel = 0;
  for (const ChannelGroup& group : channel_groups()) {
    const std::vector<float>& data = s.*group.member;
    check(data.size() == group.names.size() * s.plane(), "synth sample: ", group.names[0],
          " has ", data.size(), " values, expected ", group.names.size() * s.plane());
    std::copy(data.begin(), data.end(), image.plane(channel));
    channel += static_cast<int>(group.names.size());
  }
  image.set_metadata(key("generator_version"), kSynthGeneratorVersion);
  image.set_metadata(key("seed"), std::to_string(s.run_seed));
  image.set_metadata(key("sample_index"), std::to_string(s.index));
  image.set_metadata(key("sample_seed"), std::to_string(s.sample_seed));
  image.set_metadata(key("light_sh"), format_numbers(s.light.data(), s.light.size()));
  const double pose[3] = {s.pose.roll_deg, s.pose.pitch_deg, s.pose.yaw_deg};
  image.set_metadata(key("pose_deg"), format_numbers(pose, 3));
  image.set_metadata(key("fov_deg"), format_numbers(&s.fov_deg, 1));
  image.set_metadata(key("light_source"), s.light_source);
  image.set_metadata(key("shape"), s.shape);
  image.set_metadata(key("settings"), s.settings);
  // Only when not v1's framing / when an edge was simulated: v1 samples stay as they were.
  if (!s.framing.empty()) image.set_metadata(key("framing"), s.framing);
  if (s.photo_edges > 0) image.set_metadata(key("photo_edges"), std::to_string(s.photo_edges));
  if (!s.albedo_texture.empty()) image.set_metadata(key("albedo_texture"), s.albedo_texture);
  if (!s.landmarks.empty()) image.set_metadata(key("landmarks"), format_numbers(s.landmarks.data(), s.landmarks.size()));
  image.set_metadata(key("layout"),
                     "light_sh: 27 SH coefficients, channel-major R0..R8 G0..G8 B0..B8; "
                     "pose_deg: roll pitch yaw; camera at (0,0,5.8) looking down -Z; "
                     "fov_deg: horizontal field of view");
  return image;
}

SynthSample synth_sample_from_image(const LayeredImage& image, const std::string& source) {
  SynthSample s;
  s.width = image.width;
  s.height = image.height;
  for (const ChannelGroup& group : channel_groups()) {
    std::vector<float>& data = s.*group.member;
    data.resize(group.names.size() * s.plane());
    for (size_t k = 0; k < group.names.size(); ++k) {
      const float* plane = image.plane(image.require_channel(group.names[k], source));
      std::copy(plane, plane + s.plane(), data.begin() + k * s.plane());
    }
  }
  SynthSampleInfo info;
  read_info(image, source, info);
  check(info.generator_version == kSynthGeneratorVersion, "sample '", source,
        "' was written by generator ", info.generator_version, ", this is ",
        kSynthGeneratorVersion, ": regenerate it");
  s.run_seed = info.run_seed;
  s.sample_seed = info.sample_seed;
  s.index = info.index;
  s.pose = info.pose;
  s.fov_deg = info.fov_deg;
  s.light_source = info.light_source;
  const auto light = parse_numbers(require(image, "light_sh", source), sh::kLightCoeffCount,
                                    "light_sh", source);
  std::copy(light.begin(), light.end(), s.light.begin());
  if (const std::string* shape = image.find_metadata(key("shape"))) s.shape = *shape;
  if (const std::string* framing = image.find_metadata(key("framing"))) s.framing = *framing;
  if (const std::string* landmarks = image.find_metadata(key("landmarks")))
    s.landmarks = parse_numbers(*landmarks, 136, "landmarks", source);
  if (const std::string* edges = image.find_metadata(key("photo_edges")))
    s.photo_edges = (*edges == "1" || *edges == "2") ? std::stoi(*edges) : 0;
  s.settings = info.settings;
  return s;
}

void write_synth_sample(const std::string& path, const SynthSample& sample) {
  write_exr_atomically(path, synth_sample_to_image(sample));
}

SynthSample read_synth_sample(const std::string& path) {
  return synth_sample_from_image(read_exr(path, kPrefix), path);
}

SynthSampleInfo read_synth_sample_info(const std::string& path) {
  const LayeredImage header = read_exr_header(path, kPrefix);
  SynthSampleInfo info;
  read_info(header, path, info);
  return info;
}

}  // namespace facetool
