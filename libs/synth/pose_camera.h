// Head pose and the pinhole camera of the paper (section 4.1): rotate by roll, pitch and yaw,
// fit the face's bounding box into [-1, 1], look at it from (0, 0, 5.8) down -Z.
#pragma once

#include <array>

#include "libs/image/crop_framing.h"
#include "libs/synth/face_mesh.h"
#include "libs/synth/random.h"

namespace facetool {

// Angles in degrees. The mesh is rotated about Z (roll), then X (pitch), then Y (yaw):
// p' = Ry(yaw) Rx(pitch) Rz(roll) p, with the neutral face looking down +Z and +Y up.
struct HeadPose {
  double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;
};

struct PoseSampling {
  double max_roll_deg = 30, max_pitch_deg = 20, max_yaw_deg = 30;
};
HeadPose sample_pose(Random& random, const PoseSampling& sampling);

// Rotates `mesh` in place, then scales and shifts it uniformly so that the bounding box of its
// fit vertices is centred at the origin with its longest side spanning [-1, 1].
void apply_pose(FaceMesh& mesh, const HeadPose& pose);

// A pinhole camera at (0, 0, distance) looking down -Z with +Y up; pixel (0, 0) is the top left.
// The image is the field of view's square framed by `framing` (libs/image/crop_framing.h): v1's
// framing shows the whole field of view; zoom z shows its 1/z part around the framing's centre,
// the same picture enlarged z times (only the zoom and centre matter here, not the border fill).
struct Camera {
  int width = 128;
  int height = 128;
  double horizontal_fov_deg = 22.5;
  double distance = 5.8;
  CropFraming framing;

  Vec3f eye() const { return {0.0f, 0.0f, static_cast<float>(distance)}; }
  // Unit direction of the ray through the centre of pixel (x, y).
  Vec3f ray_direction(double x, double y) const;
  // Where the point `p` projects: pixel coordinates (centres at integers), the inverse of
  // ray_direction. `p` must be in front of the camera (p.z < distance).
  std::array<double, 2> project(const Vec3f& p) const;
};

struct CameraSampling {
  int width = 128, height = 128;
  double min_fov_deg = 20, max_fov_deg = 25;
  CropFraming framing;  // copied into every camera (the field of view is still drawn as before)
};
Camera sample_camera(Random& random, const CameraSampling& sampling);

}  // namespace facetool
