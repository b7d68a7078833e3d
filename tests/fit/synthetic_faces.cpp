// Synthetic faces with known truth for the fit tests.
#include "synthetic_faces.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "libs/synth/random.h"
#include "libs/synth/ray_scene.h"

namespace facetool::testing {

std::string fit_face_model_dir() {
  const std::string dir = std::string(FACETOOL_SHARED_DIR) + "/assets/ict-facekit/FaceXModel";
  return std::filesystem::exists(dir) ? dir : std::string();
}

SyntheticFace make_synthetic_face(const FaceModel& model, uint64_t seed, const HeadPose& pose, int size,
                                  double fov_deg, bool expressions) {
  SyntheticFace f;
  f.pose = pose;
  Random random(seed);
  ShapeSampling sampling;
  sampling.max_active_expressions = expressions ? 3 : 0;
  sampling.max_expression_weight = 0.6;
  f.weights = model.sample(random, sampling);
  f.mesh = model.build(f.weights);
  apply_pose(f.mesh, pose);
  f.camera.width = f.camera.height = size;
  f.camera.horizontal_fov_deg = fov_deg;
  const std::vector<Vec3f> normals = vertex_normals(f.mesh);
  const RayScene scene(f.mesh.positions, f.mesh.triangles);
  f.truth = cast_primary_rays(scene, f.mesh, normals, f.camera);
  const double half = std::tan(0.5 * fov_deg * 3.14159265358979323846 / 180);
  for (int i = 0; i < kLandmarkCount; ++i) {
    const Vec3f p = f.mesh.positions[model.landmarks()[i]];
    const double depth = f.camera.distance - p.z;
    f.landmarks[i] = {(p.x / depth / half + 1) * 0.5 * size - 0.5, (1 - p.y / depth / half) * 0.5 * size - 0.5};
  }
  f.picture.width = f.picture.height = size;
  f.picture.pixels.assign(static_cast<size_t>(size) * size * 3, 0.05f);
  const Vec3f light = normalized(Vec3f{0.3f, 0.4f, 1.0f});
  for (size_t p = 0; p < f.truth.pixel_count(); ++p) {
    if (!f.truth.head[p]) continue;
    const float shade = 0.1f + 0.6f * std::max(0.0f, dot(f.truth.normal[p], light));
    const float tint[3] = {1.0f, 0.8f, 0.7f};
    for (int c = 0; c < 3; ++c) f.picture.pixels[p * 3 + c] = shade * tint[c];
  }
  return f;
}

double mean_normal_error_deg(const SyntheticFace& face, const std::vector<float>& normal,
                             const std::vector<uint8_t>& covered, double* coverage) {
  const size_t plane = face.truth.pixel_count();
  double sum = 0;
  int64_t count = 0, inside = 0;
  for (size_t p = 0; p < plane; ++p) {
    if (!face.truth.mask[p]) continue;
    ++inside;
    if (!covered[p]) continue;
    const Vec3f n{normal[p], normal[plane + p], normal[2 * plane + p]};
    const double c = std::clamp(static_cast<double>(dot(n, face.truth.normal[p])), -1.0, 1.0);
    sum += std::acos(c) * 180 / 3.14159265358979323846;
    ++count;
  }
  if (coverage) *coverage = inside > 0 ? static_cast<double>(count) / inside : 0.0;
  return count > 0 ? sum / count : 180.0;
}

}  // namespace facetool::testing
