// Hemisphere-only ray casting in packets of 16 and SH accumulation of the open directions.
#include "libs/synth/visibility.h"

#include <algorithm>
#include <cmath>

#include "core/sh/sh_basis.h"
#include "core/sh/sphere_samples.h"
#include "core/util/error.h"

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
  return integrate_group(scene, &p, &n, 1, offset, out);
}

int64_t VisibilitySampler::integrate_group(const RayScene& scene, const Vec3f* p, const Vec3f* n,
                                           int count, float offset, float* out) const {
  check(count >= 1 && count <= 16, "integrate_group: 1..16 points, got ", count);
  // Every lane of the packet is written before every call: a lane that is not cast in this
  // packet (beyond `count`, or facing away from the direction) holds a harmless finite ray
  // (origin 0, direction +Z) and is masked off, so Embree never reads uninitialised memory.
  RayScene::Packet16 packet;
  Vec3f origins[16];
  for (int k = 0; k < 16; ++k) origins[k] = k < count ? p[k] + n[k] * offset : Vec3f{0, 0, 0};
  for (int k = 0; k < count; ++k)
    check(std::isfinite(origins[k].x) && std::isfinite(origins[k].y) &&
              std::isfinite(origins[k].z) && std::isfinite(n[k].x) && std::isfinite(n[k].y) &&
              std::isfinite(n[k].z),
          "integrate_group: point ", k, " has a non-finite position or normal");
  double sum[16][9] = {};
  int64_t cast = 0;
  const int directions = direction_count();
  for (int s = 0; s < directions; ++s) {
    const float dx = dir_x_[s], dy = dir_y_[s], dz = dir_z_[s];
    uint32_t active = 0;
    for (int k = 0; k < 16; ++k) {
      const bool cast_here = k < count && dx * n[k].x + dy * n[k].y + dz * n[k].z > 0.0f;
      if (cast_here) active |= 1u << k;  // below the surface: occluded, not cast
      packet.org_x[k] = cast_here ? origins[k].x : 0.0f;
      packet.org_y[k] = cast_here ? origins[k].y : 0.0f;
      packet.org_z[k] = cast_here ? origins[k].z : 0.0f;
      packet.dir_x[k] = cast_here ? dx : 0.0f;
      packet.dir_y[k] = cast_here ? dy : 0.0f;
      packet.dir_z[k] = cast_here ? dz : 1.0f;
    }
    if (!active) continue;
    packet.active = active;
    const uint32_t open = active & ~scene.occluded16(packet, 0.0f);
    cast += __builtin_popcount(active);
    if (!open) continue;
    const float* y = &basis_[static_cast<size_t>(s) * 9];
    for (int k = 0; k < count; ++k)
      if ((open >> k) & 1u)
        for (int i = 0; i < 9; ++i) sum[k][i] += y[i];
  }
  for (int k = 0; k < count; ++k)
    for (int i = 0; i < 9; ++i) out[9 * k + i] = static_cast<float>(sum[k][i] * weight_);
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

int64_t integrate_visibility_image(const VisibilitySampler& sampler, const RayScene& scene,
                                   const std::vector<Vec3f>& position,
                                   const std::vector<Vec3f>& normal,
                                   const std::vector<uint8_t>& domain, int width, int height,
                                   float offset, std::vector<float>& planar_out) {
  const size_t plane = static_cast<size_t>(width) * height;
  check(domain.size() == plane && position.size() == plane && normal.size() == plane,
        "integrate_visibility_image: buffers do not match ", width, "x", height);
  planar_out.assign(9 * plane, 0.0f);
  // Domain pixels in 4x4 tiles, so that each group of 16 holds neighbours.
  std::vector<int> cast_pixels;
  cast_pixels.reserve(plane);
  for (int ty = 0; ty < height; ty += 4)
    for (int tx = 0; tx < width; tx += 4)
      for (int y = ty; y < std::min(ty + 4, height); ++y)
        for (int x = tx; x < std::min(tx + 4, width); ++x) {
          const size_t p = static_cast<size_t>(y) * width + x;
          if (domain[p]) cast_pixels.push_back(static_cast<int>(p));
        }
  int64_t rays = 0;
  for (size_t first = 0; first < cast_pixels.size(); first += 16) {
    const int count = static_cast<int>(std::min<size_t>(16, cast_pixels.size() - first));
    Vec3f points[16], normals_here[16];
    float visibility[16 * 9];
    for (int k = 0; k < count; ++k) {
      points[k] = position[cast_pixels[first + k]];
      normals_here[k] = normal[cast_pixels[first + k]];
    }
    rays += sampler.integrate_group(scene, points, normals_here, count, offset, visibility);
    for (int k = 0; k < count; ++k)
      for (int i = 0; i < 9; ++i)
        planar_out[i * plane + cast_pixels[first + k]] = visibility[9 * k + i];
  }
  return rays;
}

}  // namespace facetool
