// The light presets a view page offers: the photo's own faces' lights, the run's other photos', and the lights facetool ships.
#pragma once

#include <string>
#include <vector>

#include "libs/view/view_inputs.h"
#include "libs/view/view_page.h"

namespace facetool::view {

// The lights facetool ships (lights/*.json in the source tree, share/facetool/lights/ installed:
// the SH lights of CC0 HDR maps, scripts/make-lights.sh), embedded in the program at build time;
// each named "HDR map: <name>".
const std::vector<LightPreset>& shipped_light_presets();

// A page's presets menu: each face of `photo` ("this photo, face K"), then `run_lights` but the
// one named after `photo` ("light of <name>"), then the shipped lights.
std::vector<LightPreset> page_presets(const ViewPhoto& photo, const std::vector<LightPreset>& run_lights);

}  // namespace facetool::view
