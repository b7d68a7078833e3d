// The view page's inputs from a photo decomposed in memory (Python's facetool.Photo), as the folder reader makes them.
#pragma once

#include <string>

#include "libs/photo/photo_pipeline.h"
#include "libs/view/view_inputs.h"

namespace facetool::view {

// What read_view_photo reads from the folder infer writes for `photo` with infer's --feather
// `feather` and face region `forehead` (the resolved --face-region): the same ViewPhoto, built
// from memory; its layer PNGs encoded as infer encodes them. `name` titles the page. Throws
// facetool::Error for a photo the page cannot show (no face, too many, larger than max_side).
ViewPhoto view_photo_from(const DecomposedPhoto& photo, const std::string& name, double feather, bool forehead,
                          int max_side = 4096);

}  // namespace facetool::view
