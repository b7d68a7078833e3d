// LayeredImage: a float image with named channels and string metadata (one EXR file's content).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace facetool {

// Planar storage: channel c occupies pixels[c * width * height ...], rows top to bottom.
struct LayeredImage {
  int width = 0;
  int height = 0;
  std::vector<std::string> channel_names;
  std::vector<float> pixels;
  std::vector<std::pair<std::string, std::string>> metadata;  // name, value

  LayeredImage() = default;
  LayeredImage(int width, int height, std::vector<std::string> channel_names);

  int channel_count() const { return static_cast<int>(channel_names.size()); }
  size_t plane_size() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  // Index of the channel called `name`, or -1.
  int find_channel(const std::string& name) const;
  // Index of the channel called `name`; throws facetool::Error naming `source` if absent.
  int require_channel(const std::string& name, const std::string& source) const;
  float* plane(int channel) { return pixels.data() + channel * plane_size(); }
  const float* plane(int channel) const { return pixels.data() + channel * plane_size(); }

  void set_metadata(const std::string& name, const std::string& value);
  // The value of `name`, or nullptr.
  const std::string* find_metadata(const std::string& name) const;
};

}  // namespace facetool
