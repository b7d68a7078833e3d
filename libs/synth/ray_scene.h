// RayScene: an Embree BVH over one triangle mesh, answering closest-hit and occlusion queries.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "libs/synth/vec3.h"

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

  // Up to 16 rays as structure-of-arrays; lane k is used when bit k of `active` is set.
  struct Packet16 {
    alignas(64) float org_x[16] = {}, org_y[16] = {}, org_z[16] = {};
    alignas(64) float dir_x[16] = {}, dir_y[16] = {}, dir_z[16] = {};
    uint32_t active = 0;
  };
  // Occlusion between distance `tnear` and infinity, as one incoherent rtcOccluded16 call.
  // Bit k of the result is set when active ray k hits a triangle.
  uint32_t occluded16(const Packet16& packet, float tnear) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facetool
