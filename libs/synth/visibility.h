// Per-point visibility projected onto the 9 SH: rays in N nearly uniform directions, only those
// above the surface cast (the rest are occluded by definition), occlusion tested by Embree.
#pragma once

#include <cstdint>
#include <vector>

#include "libs/synth/ray_scene.h"
#include "libs/synth/vec3.h"

namespace facetool {

class VisibilitySampler {
 public:
  // `direction_count` directions of sh::fibonacci_sphere (the paper uses 872).
  explicit VisibilitySampler(int direction_count);

  int direction_count() const { return static_cast<int>(dir_x_.size()); }

  // v_i = 4 pi / N * sum over directions d with d.n > 0 whose ray from p + offset * n is not
  // blocked of Y_i(d). Writes 9 coefficients to `out`; returns the number of rays cast.
  int64_t integrate(const RayScene& scene, Vec3f p, Vec3f n, float offset, float out[9]) const;

  // The same for up to 16 points at once (best when they are neighbours): for each direction,
  // the rays of all points that see it above their surface go as one packet, which shares
  // the BVH traversal between similar rays. Results equal `integrate` per point up to Embree's
  // packet/single-ray rounding. Writes 9 coefficients per point to out[9 * k ...].
  int64_t integrate_group(const RayScene& scene, const Vec3f* p, const Vec3f* n, int count,
                          float offset, float* out) const;

  // The same sum with no geometry at all (every upper-hemisphere direction open): the sampled
  // hemisphere whose continuous counterpart has analytic coefficients.
  void open_hemisphere(Vec3f n, float out[9]) const;

 private:
  std::vector<float> dir_x_, dir_y_, dir_z_;
  std::vector<float> basis_;  // 9 per direction, Y_i(d) from the SH library
  float weight_;              // 4 pi / N
};

// The visibility image: for every pixel of `domain` (width x height, row-major), the 9
// coefficients at its surface point `position` with normal `normal`, cast in 4x4 tiles of 16
// neighbours (integrate_group); planar output [9][width * height], 0 outside the domain. Used by
// the synthetic generator and by the fit's rendering. Returns the number of rays cast.
int64_t integrate_visibility_image(const VisibilitySampler& sampler, const RayScene& scene,
                                   const std::vector<Vec3f>& position,
                                   const std::vector<Vec3f>& normal,
                                   const std::vector<uint8_t>& domain, int width, int height,
                                   float offset, std::vector<float>& planar_out);

}  // namespace facetool
