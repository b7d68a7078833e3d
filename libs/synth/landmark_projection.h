// The face model's 68 landmark vertices projected through the synthetic camera and framing: the
// source of the canonical photo template (libs/face/face_template.h, `facetool face-template`).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "libs/image/crop_framing.h"

namespace facetool {

// Projects the 68 landmark vertices of the neutral ICT face (FaceModel, vertex_indices.json),
// posed like a synthetic sample with zero roll, pitch and yaw (apply_pose: face region fitted
// into [-1, 1]) through the synthetic camera at its mean field of view (22.5 degrees) into a
// square crop framed by `framing` (Camera::project). Returns 68 (x, y) positions in crop units:
// (pixel centre + 0.5) / crop size, so [0, 1] spans the crop whatever its size. Throws
// facetool::Error when the model has no landmarks.
std::vector<std::array<double, 2>> project_neutral_landmarks(const std::string& face_model_directory,
                                                             double fov_deg = 22.5,
                                                             const CropFraming& framing = CropFraming{});

}  // namespace facetool
