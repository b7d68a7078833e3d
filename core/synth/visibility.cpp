// Hemisphere-only ray casting in packets of 16 and SH accumulation of the open directions.
#include "core/synth/visibility.h"

#include "core/sh/sh_basis.h"
#include "core/sh/sphere_samples.h"

namespace facetool {

VisibilitySampler::VisibilitySampler(int direction_count) {
  const std::vector<sh::Vec3> dirs = sh::fibonacci_sphere(direction_count);
  for (const sh::Vec3& d : dirs) {
    dir_x_.push_back(static_cast<float>(d[0]));
    dir_y_.push_back(static_cast<float>(d[1]));
    dir_z_.push_back(static_cast<float>(d[2]));
    double y[sh::kCoeffCount];
    sh::sh_basis(d[0], d[1], d[2], y);
    for (double value : y) basis_.push_back(static_cast<float>(value));
  }
  weight_ = static_cast<float>(4.0 * sh::ShConstants::kPi / direction_count);
}

int64_t VisibilitySampler::integrate(const RayScene& scene, Vec3f p, Vec3f n, float offset,
                                     float out[9]) const {
  const Vec3f origin = p + n * offset;
  double sum[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  alignas(64) float px[16], py[16], pz[16];
  int lane_direction[16];
  int lanes = 0;
  int64_t cast = 0;
  auto flush = [&] {
    const uint32_t blocked = scene.occluded16(origin, px, py, pz, lanes, 0.0f);
    for (int k = 0; k < lanes; ++k) {
      if (blocked & (1u << k)) continue;
      const float* y = &basis_[static_cast<size_t>(lane_direction[k]) * 9];
      for (int i = 0; i < 9; ++i) sum[i] += y[i];
    }
    cast += lanes;
    lanes = 0;
  };
  const int count = direction_count();
  for (int s = 0; s < count; ++s) {
    if (dir_x_[s] * n.x + dir_y_[s] * n.y + dir_z_[s] * n.z <= 0.0f) continue;
    px[lanes] = dir_x_[s];
    py[lanes] = dir_y_[s];
    pz[lanes] = dir_z_[s];
    lane_direction[lanes++] = s;
    if (lanes == 16) flush();
  }
  if (lanes > 0) flush();
  for (int i = 0; i < 9; ++i) out[i] = static_cast<float>(sum[i] * weight_);
  return cast;
}

void VisibilitySampler::open_hemisphere(Vec3f n, float out[9]) const {
  double sum[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (int s = 0; s < direction_count(); ++s) {
    if (dir_x_[s] * n.x + dir_y_[s] * n.y + dir_z_[s] * n.z <= 0.0f) continue;
    for (int i = 0; i < 9; ++i) sum[i] += basis_[static_cast<size_t>(s) * 9 + i];
  }
  for (int i = 0; i < 9; ++i) out[i] = static_cast<float>(sum[i] * weight_);
}

}  // namespace facetool
