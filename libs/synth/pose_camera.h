// Head pose and the pinhole camera of the paper (section 4.1): rotate by roll, pitch and yaw,
// fit the face's bounding box into [-1, 1], look at it from (0, 0, 5.8) down -Z.
#pragma once

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
struct Camera {
  int width = 128;
  int height = 128;
  double horizontal_fov_deg = 22.5;
  double distance = 5.8;

  Vec3f eye() const { return {0.0f, 0.0f, static_cast<float>(distance)}; }
  // Unit direction of the ray through the centre of pixel (x, y).
  Vec3f ray_direction(double x, double y) const;
};

struct CameraSampling {
  int width = 128, height = 128;
  double min_fov_deg = 20, max_fov_deg = 25;
};
Camera sample_camera(Random& random, const CameraSampling& sampling);

}  // namespace facetool
