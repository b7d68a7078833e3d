// Synthetic faces with known truth for the fit tests: a random ICT shape in a chosen pose seen
// by synth's camera, its true landmarks, normals and mask, and a shaded picture for dlib.
#pragma once

#include <memory>
#include <string>

#include "libs/face/landmarks68.h"
#include "libs/io/image_io.h"
#include "libs/synth/face_model.h"
#include "libs/synth/gbuffer.h"
#include "libs/synth/pose_camera.h"

namespace facetool::testing {

// The ICT model folder under ../shared, or "" when absent.
std::string fit_face_model_dir();

struct SyntheticFace {
  HeadPose pose;
  Camera camera;
  ShapeWeights weights;
  FaceMesh mesh;        // posed, in synth's world frame (camera at (0, 0, distance))
  GBuffer truth;        // synth's primary rays: true normals (camera frame), mask
  Landmarks68 landmarks{};  // the landmark vertices projected, pixels
  RgbImage picture;     // Lambertian shading of the truth under a frontal light, grey background
};

// Identity weights ~ N(0, 1) truncated at 2.5 from `seed`, expressions 0 unless `expressions`
// (then up to 3 active, in [0, 0.6]).
SyntheticFace make_synthetic_face(const FaceModel& model, uint64_t seed, const HeadPose& pose,
                                  int size = 256, double fov_deg = 22.5, bool expressions = false);

// Mean angle (degrees) between the fitted normals (planar [3]) and the truth over the pixels of
// the true mask that the fit also covers; `coverage` gets the covered fraction of the true mask.
double mean_normal_error_deg(const SyntheticFace& face, const std::vector<float>& normal,
                             const std::vector<uint8_t>& covered, double* coverage);

}  // namespace facetool::testing
