// Pose sampling and application, camera rays.
#include "libs/synth/pose_camera.h"
#include "core/util/math_constants.h"

#include <algorithm>
#include <cmath>

namespace facetool {
namespace {
constexpr double kDegree = kPi / 180.0;
}

HeadPose sample_pose(Random& random, const PoseSampling& sampling) {
  HeadPose pose;
  pose.roll_deg = random.uniform(-sampling.max_roll_deg, sampling.max_roll_deg);
  pose.pitch_deg = random.uniform(-sampling.max_pitch_deg, sampling.max_pitch_deg);
  pose.yaw_deg = random.uniform(-sampling.max_yaw_deg, sampling.max_yaw_deg);
  return pose;
}

void apply_pose(FaceMesh& mesh, const HeadPose& pose) {
  const Mat3f rotation = rotation_y(static_cast<float>(pose.yaw_deg * kDegree)) *
                         rotation_x(static_cast<float>(pose.pitch_deg * kDegree)) *
                         rotation_z(static_cast<float>(pose.roll_deg * kDegree));
  for (Vec3f& p : mesh.positions) p = rotation * p;
  Vec3f low{1e30f, 1e30f, 1e30f}, high{-1e30f, -1e30f, -1e30f};
  for (int32_t v : mesh.fit_vertices)
    for (int k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], mesh.positions[v][k]);
      high[k] = std::max(high[k], mesh.positions[v][k]);
    }
  const Vec3f centre = (low + high) * 0.5f;
  const float extent = std::max({high.x - low.x, high.y - low.y, high.z - low.z});
  const float scale = extent > 0 ? 2.0f / extent : 1.0f;
  for (Vec3f& p : mesh.positions) p = (p - centre) * scale;
}

// Pixel (x, y) in v1's image plane coordinates u, v ([-1, 1] across v1's image): the framing's
// inverse, u = (2 (x + 0.5) / W - 1) / zoom + (2 centre_x - 1) (and v with y flipped). For v1
// (zoom 1, centre 0.5) this is bit for bit the expression without a framing.
Vec3f Camera::ray_direction(double x, double y) const {
  const double half_width = std::tan(0.5 * horizontal_fov_deg * kDegree);
  const double half_height = half_width * height / width;
  const double u = ((2.0 * (x + 0.5) / width - 1.0) / framing.zoom + (2.0 * framing.centre_x - 1.0)) * half_width;
  const double v = ((1.0 - 2.0 * (y + 0.5) / height) / framing.zoom + (1.0 - 2.0 * framing.centre_y)) * half_height;
  return normalized(Vec3f{static_cast<float>(u), static_cast<float>(v), -1.0f});
}

std::array<double, 2> Camera::project(const Vec3f& p) const {
  const double half_width = std::tan(0.5 * horizontal_fov_deg * kDegree);
  const double half_height = half_width * height / width;
  const double depth = distance - p.z;  // along -Z from the eye
  const double u = p.x / depth / half_width, v = p.y / depth / half_height;  // v1's [-1, 1]
  const double fu = (u - (2.0 * framing.centre_x - 1.0)) * framing.zoom;
  const double fv = (v - (1.0 - 2.0 * framing.centre_y)) * framing.zoom;
  return {(fu + 1.0) * 0.5 * width - 0.5, (1.0 - fv) * 0.5 * height - 0.5};
}

Camera sample_camera(Random& random, const CameraSampling& sampling) {
  Camera camera;
  camera.width = sampling.width;
  camera.height = sampling.height;
  camera.horizontal_fov_deg = random.uniform(sampling.min_fov_deg, sampling.max_fov_deg);
  camera.framing = sampling.framing;
  return camera;
}

}  // namespace facetool
