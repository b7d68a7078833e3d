// GBuffer: what primary rays from the camera see per pixel (mask, position, smooth normal,
// depth, and where on the reference face the hit lies, for the albedo).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "libs/synth/face_mesh.h"
#include "libs/synth/pose_camera.h"
#include "libs/synth/ray_scene.h"

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

// Pixels [x0, x1) x [y0, y1) of a width x height image (the rest stays empty).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The same for any camera: `ray(x, y, origin, direction)` gives the ray through the centre of
// pixel (x, y) (e.g. parallel rays for an orthographic camera); depth is eye_z - position.z.
// Only the pixels of `rect` are cast (the whole image when it is empty).
template <typename RayFunction>
GBuffer cast_rays(const RayScene& scene, const FaceMesh& mesh, const std::vector<Vec3f>& normals,
                  int width, int height, float eye_z, const RayFunction& ray, PixelRect rect = {});

// One pixel of a G-buffer from the hit of the ray (origin, direction); false for a miss or a
// back face (then the pixel stays empty). Shared by cast_primary_rays and cast_rays.
bool shade_primary_hit(const RayScene& scene, const FaceMesh& mesh, const std::vector<Vec3f>& normals,
                       Vec3f origin, Vec3f direction, float eye_z, size_t pixel, GBuffer& g);
// An empty G-buffer of width x height.
GBuffer empty_gbuffer(int width, int height);

template <typename RayFunction>
GBuffer cast_rays(const RayScene& scene, const FaceMesh& mesh, const std::vector<Vec3f>& normals,
                  int width, int height, float eye_z, const RayFunction& ray, PixelRect rect) {
  GBuffer g = empty_gbuffer(width, height);
  if (rect.x1 <= rect.x0 || rect.y1 <= rect.y0) rect = {0, 0, width, height};
  for (int y = std::max(0, rect.y0); y < std::min(height, rect.y1); ++y)
    for (int x = std::max(0, rect.x0); x < std::min(width, rect.x1); ++x) {
      Vec3f origin, direction;
      ray(x, y, origin, direction);
      shade_primary_hit(scene, mesh, normals, origin, direction, eye_z,
                        static_cast<size_t>(y) * width + x, g);
    }
  return g;
}

// The mask eroded by one pixel (3x3 neighbourhood; pixels beyond the border count as outside),
// the region the paper's losses use.
std::vector<uint8_t> erode_mask(const std::vector<uint8_t>& mask, int width, int height);
std::vector<float> erode_mask(const std::vector<float>& mask, int width, int height);
// The mask dilated by one pixel (3x3 neighbourhood): the pixels whose visibility is computed.
std::vector<uint8_t> dilate_mask(const std::vector<uint8_t>& mask, int width, int height);

}  // namespace facetool
