// `infer --aligned`: one ready face crop brought to the network's input, aligned by its
// landmarks when a face is found in it, otherwise stretched to the input as it is.
#pragma once

#include <string>
#include <vector>

#include "libs/photo/photo_pipeline.h"

namespace facetool {

struct AlignedInput {
  FaceCrop crop;              // crop.rgb: planar linear RGB [3][size*size]; the alignment when by_landmarks
  bool by_landmarks = false;  // aligned by its landmarks (false: stretched)
  std::string reason;         // why it was stretched: no face found (empty otherwise)
};

// Reads `path` (8-bit: sRGB; EXR/HDR/PFM: linear) and, with a detector, looks for its best face
// (the photo options' detection, padded as for photos, one face): found, the crop is the
// similarity alignment of photos at the options' framing (its border fill beyond the image's
// edge); not found,
// or without a detector (--stretch), the image is resized to size x size as before.
AlignedInput read_aligned_input(const std::string& path, int size, FaceDetector* detector,
                                const PhotoInferOptions& options);

}  // namespace facetool
