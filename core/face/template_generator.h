// Derives the canonical 68-point template from the synthetic pipeline (the ICT face model's
// landmark vertices, neutral shape and pose, the synthetic camera and framing).
#pragma once

#include <string>

#include "core/face/point2.h"

namespace facetool {

// Projects the 68 landmark vertices of the neutral ICT face (FaceModel, vertex_indices.json),
// posed like a synthetic sample with zero roll, pitch and yaw (apply_pose: face region fitted
// into [-1, 1]) through the synthetic camera at its mean field of view (22.5 degrees) into a
// square crop. Returns positions in crop units: (pixel centre + 0.5) / crop size, so [0, 1]
// spans the crop whatever its size. Throws facetool::Error when the model has no landmarks.
Landmarks68 generate_canonical_template(const std::string& face_model_directory,
                                        double fov_deg = 22.5);

// C++ source of the table in face_template.cpp for `landmarks` (what `facetool face-template`
// prints).
std::string template_table_source(const Landmarks68& landmarks);

}  // namespace facetool
