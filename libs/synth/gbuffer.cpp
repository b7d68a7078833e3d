// Rasterisation by ray casting and mask erosion.
#include "libs/synth/gbuffer.h"

namespace facetool {

GBuffer empty_gbuffer(int width, int height) {
  GBuffer g;
  g.width = width;
  g.height = height;
  const size_t count = static_cast<size_t>(width) * height;
  g.head.assign(count, 0);
  g.mask.assign(count, 0);
  g.position.assign(count, Vec3f{});
  g.normal.assign(count, Vec3f{});
  g.depth.assign(count, 0.0f);
  g.reference.assign(count, Vec3f{});
  g.part.assign(count, FacePart::kOther);
  return g;
}

bool shade_primary_hit(const RayScene& scene, const FaceMesh& mesh, const std::vector<Vec3f>& normals,
                       Vec3f origin, Vec3f direction, float eye_z, size_t p, GBuffer& g) {
  const RayScene::Hit hit = scene.intersect(origin, direction);
  if (hit.triangle < 0) return false;
  const auto& t = mesh.triangles[hit.triangle];
  const Vec3f a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
  if (dot(cross(b - a, c - a), direction) >= 0.0f) return false;  // back face
  const float w0 = 1.0f - hit.u - hit.v, w1 = hit.u, w2 = hit.v;
  g.head[p] = 1;
  g.mask[p] = is_face_region_part(mesh.triangle_parts[hit.triangle]) ? 1 : 0;
  g.position[p] = a * w0 + b * w1 + c * w2;
  g.normal[p] = normalized(normals[t[0]] * w0 + normals[t[1]] * w1 + normals[t[2]] * w2);
  g.depth[p] = eye_z - g.position[p].z;
  const auto& r = mesh.reference_positions;
  g.reference[p] = r[t[0]] * w0 + r[t[1]] * w1 + r[t[2]] * w2;
  g.part[p] = mesh.triangle_parts[hit.triangle];
  return true;
}

GBuffer cast_primary_rays(const RayScene& scene, const FaceMesh& mesh,
                          const std::vector<Vec3f>& normals, const Camera& camera) {
  const Vec3f eye = camera.eye();
  return cast_rays(scene, mesh, normals, camera.width, camera.height, eye.z,
                   [&](int x, int y, Vec3f& origin, Vec3f& direction) {
                     origin = eye;
                     direction = camera.ray_direction(x, y);
                   });
}

namespace {
template <typename T>
std::vector<T> erode(const std::vector<T>& mask, int width, int height) {
  std::vector<T> out(mask.size(), T(0));
  for (int y = 1; y + 1 < height; ++y)
    for (int x = 1; x + 1 < width; ++x) {
      bool inside = true;
      for (int dy = -1; dy <= 1 && inside; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (!(mask[static_cast<size_t>(y + dy) * width + x + dx] > T(0.5))) {
            inside = false;
            break;
          }
      if (inside) out[static_cast<size_t>(y) * width + x] = T(1);
    }
  return out;
}
}  // namespace

std::vector<uint8_t> dilate_mask(const std::vector<uint8_t>& mask, int width, int height) {
  std::vector<uint8_t> out(mask.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (!mask[static_cast<size_t>(y) * width + x]) continue;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < width && yy < height)
            out[static_cast<size_t>(yy) * width + xx] = 1;
        }
    }
  return out;
}

std::vector<uint8_t> erode_mask(const std::vector<uint8_t>& mask, int width, int height) {
  return erode(mask, width, height);
}
std::vector<float> erode_mask(const std::vector<float>& mask, int width, int height) {
  return erode(mask, width, height);
}

}  // namespace facetool
