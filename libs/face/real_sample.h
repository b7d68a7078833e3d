// RealSample: one aligned real-photo face in the dataset layout of synthetic samples (EXR with
// R G B and mask channels and facetool: attributes; docs/photos.md, "Real-photo datasets").
#pragma once

#include <string>

#include "libs/face/face_crops.h"
#include "libs/io/layered_image.h"
#include "libs/io/sample_files.h"

namespace facetool {

// The sample of `crop`: channels R G B (the aligned crop, linear) and mask (1 inside the face
// mask); attributes facetool:generator_version, facetool:source (`source`), facetool:landmarks
// (136 numbers x0 y0 x1 y1 ..., crop pixels), facetool:transform (a00 a01 a02 a10 a11 a12 of
// the 2x3 similarity photo -> crop), facetool:detection_score, facetool:mask_kind, and
// facetool:framing (framing_text) when `framing` is not v1's.
LayeredImage real_sample_image(const FaceCrop& crop, const std::string& source, bool forehead,
                               const CropFraming& framing = CropFraming{});

// The facetool:source of a real sample file, or "" when it is unreadable or not a real sample
// of this generator version (for resuming).
std::string read_real_sample_source(const std::string& path);

// Fraction of the crop's mask pixels that map outside the photo (faces cut by its edge).
double mask_fraction_outside_photo(const FaceCrop& crop, int photo_width, int photo_height);

}  // namespace facetool
