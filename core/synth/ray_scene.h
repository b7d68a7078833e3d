// RayScene: an Embree BVH over one triangle mesh, answering closest-hit and occlusion queries.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/synth/vec3.h"

namespace facetool {

class RayScene {
 public:
  // Builds the BVH (the arrays are copied). Throws facetool::Error if Embree fails.
  RayScene(const std::vector<Vec3f>& positions,
           const std::vector<std::array<int32_t, 3>>& triangles);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  struct Hit {
    int32_t triangle = -1;  // -1: the ray hit nothing
    float u = 0, v = 0;     // barycentrics of corners 1 and 2
    float distance = 0;
  };
  Hit intersect(Vec3f origin, Vec3f direction) const;

  // Occlusion of up to 16 rays leaving `origin` along the given unit directions (lanes
  // [0, count) are used) between distances tnear and infinity. Bit k of the result is set when
  // ray k hits a triangle. Rays are tested as one incoherent rtcOccluded16 packet.
  uint32_t occluded16(Vec3f origin, const float* dir_x, const float* dir_y, const float* dir_z,
                      int count, float tnear) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facetool
