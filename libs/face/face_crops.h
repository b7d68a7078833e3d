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
  std::vector<float> mask;            // [S*S], 1 inside the mask polygon
};

// Aligns and crops one face (landmarks in photo pixels).
FaceCrop crop_face(const RgbImage& photo, const DetectedFace& face, int crop_size,
                   bool extend_forehead);

}  // namespace facetool
