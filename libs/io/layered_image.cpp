// LayeredImage channel and metadata lookup.
#include "libs/io/layered_image.h"

#include "core/util/error.h"

namespace facetool {

LayeredImage::LayeredImage(int w, int h, std::vector<std::string> names)
    : width(w), height(h), channel_names(std::move(names)) {
  check(w > 0 && h > 0, "LayeredImage: size must be positive, got ", w, "x", h);
  pixels.assign(plane_size() * channel_names.size(), 0.0f);
}

int LayeredImage::find_channel(const std::string& name) const {
  for (size_t c = 0; c < channel_names.size(); ++c)
    if (channel_names[c] == name) return static_cast<int>(c);
  return -1;
}

int LayeredImage::require_channel(const std::string& name, const std::string& source) const {
  const int index = find_channel(name);
  check(index >= 0, "'", source, "' has no channel '", name,
        "'; it was not written by this version of facetool synth: regenerate it");
  return index;
}

void LayeredImage::set_metadata(const std::string& name, const std::string& value) {
  for (auto& entry : metadata)
    if (entry.first == name) {
      entry.second = value;
      return;
    }
  metadata.emplace_back(name, value);
}

const std::string* LayeredImage::find_metadata(const std::string& name) const {
  for (const auto& entry : metadata)
    if (entry.first == name) return &entry.second;
  return nullptr;
}

}  // namespace facetool
