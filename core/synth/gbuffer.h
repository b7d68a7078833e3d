// GBuffer: what primary rays from the camera see per pixel (mask, position, smooth normal,
// depth, and where on the reference face the hit lies, for the albedo).
#pragma once

#include <cstdint>
#include <vector>

#include "core/synth/face_mesh.h"
#include "core/synth/pose_camera.h"
#include "core/synth/ray_scene.h"

namespace facetool {

struct GBuffer {
  int width = 0, height = 0;
  std::vector<uint8_t> head;          // 1 where a front face of the kept geometry is seen
  std::vector<uint8_t> mask;          // 1 where that face is in the face region
                                      // (is_face_region_part): the sample's mask
  std::vector<Vec3f> position;        // world space (= camera axes, camera at +Z)
  std::vector<Vec3f> normal;          // unit, interpolated vertex normals, world space
  std::vector<float> depth;           // camera-space depth: distance along -Z from the camera
  std::vector<Vec3f> reference;       // the hit point on the neutral reference face
  std::vector<FacePart> part;
  size_t pixel_count() const { return head.size(); }
};

// One ray per pixel centre. A hit on the back of a triangle (seen through the mouth opening,
// where the oral cavity was removed) is not part of the head nor of the mask.
GBuffer cast_primary_rays(const RayScene& scene, const FaceMesh& mesh,
                          const std::vector<Vec3f>& normals, const Camera& camera);

// The mask eroded by one pixel (3x3 neighbourhood; pixels beyond the border count as outside),
// the region the paper's losses use.
std::vector<uint8_t> erode_mask(const std::vector<uint8_t>& mask, int width, int height);
std::vector<float> erode_mask(const std::vector<float>& mask, int width, int height);
// The mask dilated by one pixel (3x3 neighbourhood): the pixels whose visibility is computed.
std::vector<uint8_t> dilate_mask(const std::vector<uint8_t>& mask, int width, int height);

}  // namespace facetool
