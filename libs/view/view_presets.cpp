// The view page's light presets: the photo's faces, the run's photos, and the shipped HDR-map lights.
#include "libs/view/view_presets.h"

#include <sstream>

#include "core/util/error.h"
#include "libs/light/light_formats.h"

namespace facetool::view {
namespace page_files {
const char* kernel_source(const std::string& file_name);  // generated: libs/view/page/* and lights/*.json embedded
}  // namespace page_files

const std::vector<LightPreset>& shipped_light_presets() {
  static const std::vector<LightPreset> presets = [] {
    std::vector<LightPreset> out;
    std::istringstream names(FACETOOL_VIEW_SHIPPED_LIGHTS);  // "name,name,..." (libs/view/CMakeLists.txt)
    for (std::string name; std::getline(names, name, ',');) {
      if (name.empty()) continue;
      const char* text = page_files::kernel_source(name + ".json");
      check(text != nullptr, "view page: the shipped light '", name, ".json' is not embedded (a build error)");
      out.push_back({"HDR map: " + name, light::parse_light(text, light::Format::Facetool, name + ".json").light});
    }
    return out;
  }();
  return presets;
}

std::vector<LightPreset> page_presets(const ViewPhoto& photo, const std::vector<LightPreset>& run_lights) {
  std::vector<LightPreset> presets;
  for (size_t k = 0; k < photo.faces.size(); ++k)
    presets.push_back({"this photo, face " + std::to_string(k), photo.faces[k].photo_light});
  for (const LightPreset& p : run_lights)
    if (p.name != "light of " + photo.name) presets.push_back(p);
  for (const LightPreset& p : shipped_light_presets()) presets.push_back(p);
  return presets;
}

}  // namespace facetool::view
