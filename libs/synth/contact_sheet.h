// Contact sheets: one row per sample (image, albedo, normal, shading, ambient visibility) in a
// PNG, so a person can look at a batch of samples.
#pragma once

#include <string>
#include <vector>

#include "libs/io/image_io.h"
#include "libs/synth/synth_sample.h"

namespace facetool {

// Columns: image; albedo; normal as (n + 1) / 2; shading = image / albedo on the mask; ambient
// visibility v_0 / sqrt(pi) (the open fraction of the hemisphere: 1 for an unoccluded point) on
// the mask. Colour columns are shown sRGB-encoded, normal and visibility mapped linearly.
RgbImage make_contact_sheet(const std::vector<SynthSample>& samples);
void write_contact_sheet(const std::string& png_path, const std::vector<SynthSample>& samples);

}  // namespace facetool
