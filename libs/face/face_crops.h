// FaceCrop: one detected face of a photo aligned into the network's crop, with its mask.
#pragma once

#include <vector>

#include "libs/face/face_alignment.h"
#include "libs/face/face_detector.h"

namespace facetool {

struct FaceCrop {
  DetectedFace face;
  FaceAlignment alignment;
  std::vector<float> rgb;             // planar linear RGB [3][S*S]
  std::vector<Point2> mask_polygon;   // crop coordinates
  std::vector<float> mask;            // [S*S], 1 inside the mask polygon (and, with the
                                      // ring-mean border fill, inside the photo)
  std::vector<float> inside;          // [S*S], fraction of each crop pixel inside the photo
};

// Aligns and crops one face (landmarks in photo pixels) at `framing` (its zoom and centre, and
// its border fill outside the photo; with kRingMean the mask is cut where the crop leaves the
// photo, as synth cuts it: libs/image/border_fill.h).
FaceCrop crop_face(const RgbImage& photo, const DetectedFace& face, int crop_size,
                   bool extend_forehead, const CropFraming& framing = CropFraming{});

}  // namespace facetool
