// The landmark fit: camera, head pose, identity and expression weights of the ICT face model
// fitted to a face's 68 landmarks by robust, regularised least squares (Ceres Solver).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "libs/face/landmarks68.h"
#include "libs/fit/fit_basis.h"
#include "libs/synth/pose_camera.h"
#include "libs/synth/vec3.h"

namespace facetool {

// Scaled orthographic: pixel = principal point + s * (R p).xy + t (y flipped); perspective: a
// pinhole at the origin looking down -Z whose horizontal field of view over the photo's width
// is fixed, pixel = principal point + f * (R p + t).xy / -(R p + t).z. docs/fit.md says which is
// the default and why (measured on synthetic renders).
enum class FitCamera { kScaledOrthographic, kPerspective };
// Jaw landmarks 0-16 lie on the face's outline: re-choose their vertices between rounds among
// contour candidates (kContour), or keep the fixed vertices with a lower weight (kDownWeighted).
enum class JawHandling { kContour, kDownWeighted };

const char* fit_camera_name(FitCamera camera);
const char* jaw_handling_name(JawHandling jaw);

struct FitSettings {
  FitCamera camera = FitCamera::kPerspective;
  double fov_deg = 22.5;           // perspective: horizontal field of view over the photo width
  JawHandling jaw = JawHandling::kDownWeighted;
  double jaw_weight = 0.25;        // kDownWeighted: weight of the jaw landmarks (others 1)
  int contour_rounds = 3;          // kContour: solves, each after re-choosing the contour vertices
  // Per-landmark weight factors (68, multiplying the jaw weight above); empty: all 1.
  std::vector<double> landmark_weights;
  // Landmark residuals are in units of the landmarks' RMS spread about their centroid (S); the
  // priors' weights are relative to them.
  double identity_prior = 2e-3;    // lambda of sum alpha_k^2 (alpha ~ N(0, 1))
  double expression_prior = 1e-2;  // lambda of the smooth-L1 sparsity prior on beta in [0, 1]
  double expression_smoothness = 0.05;  // epsilon of sqrt(beta^2 + eps^2) - eps
  bool fit_expressions = true;
  double robust_scale = 0.06;      // Cauchy loss scale, in units of S
  int max_iterations = 20;         // Levenberg-Marquardt iterations per solve
  double function_tolerance = 1e-3;  // stop when the cost changes by less than this fraction
};

// One face's landmarks in a photo of width x height pixels (pixel centres at integers).
struct LandmarkTarget {
  Landmarks68 landmarks{};
  int width = 0, height = 0;
};

struct FaceFit {
  FitCamera camera = FitCamera::kScaledOrthographic;
  int width = 0, height = 0;
  double cx = 0, cy = 0;            // principal point, pixels ((width - 1) / 2, (height - 1) / 2)
  double focal_px = 0;              // perspective only
  double rotation[3] = {0, 0, 0};   // angle-axis, model -> camera frame
  double translation[3] = {0, 0, 0};  // perspective: model units; orthographic: pixels (z = 0)
  double scale = 1;                 // orthographic: pixels per model unit
  std::vector<double> identity, expression;
  std::array<int32_t, 68> vertices{};  // the vertex each landmark was fitted to
  double rms_px = 0;                // RMS landmark residual (all 68), pixels
  int iterations = 0;               // Levenberg-Marquardt iterations, all rounds
  double seconds = 0;               // CPU time of the fit (thread), per face

  // Camera frame: +X right, +Y up, +Z to the viewer (the project's convention). Orthographic
  // fits use pixel units in it (x = u - cx, y = cy - v), perspective ones the model's units.
  Mat3f rotation_matrix() const;
  Vec3f to_camera(Vec3f model_point) const;
  Point2 project(Vec3f camera_point) const;
  // The rotation as the synthetic generator's roll, pitch, yaw (p' = Ry Rx Rz p).
  HeadPose pose() const;
};

// What the targets of one fit_landmarks call have in common.
enum class SharedFace {
  kNothing,   // separate faces: each its own fit
  kIdentity,  // one person: one identity vector; camera, pose and expression per target
              // (`facetool fit --same-person`)
  kHead,      // one still head seen by one camera (a light stage, a tripod burst): one identity,
              // pose and expression; the targets must share the photo size (`fit --still-head`)
};

// Fits each target. A parameter block the targets share gets its prior weighted by their
// number, so that n photos of one face do not loosen it: dlib's errors and the model's misfit
// repeat from photo to photo of one face, and a prior loosened n times fits them (measured on
// Yale B, docs/benchmarks.md).
std::vector<FaceFit> fit_landmarks(const FitBasis& basis, const std::vector<LandmarkTarget>& targets,
                                   const FitSettings& settings, SharedFace shared = SharedFace::kNothing);
FaceFit fit_landmarks(const FitBasis& basis, const LandmarkTarget& target, const FitSettings& settings);

// Angle in degrees of the rotation between two poses (the geodesic distance on SO(3)).
double rotation_difference_deg(const HeadPose& a, const HeadPose& b);
Mat3f pose_rotation(const HeadPose& pose);

}  // namespace facetool
