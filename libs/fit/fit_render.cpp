// Ray casting the fitted mesh through the fit's camera, then the synthetic generator's
// visibility integration on the pixels of the face.
#include "libs/fit/fit_render.h"

#include <algorithm>
#include <cmath>

#include "libs/fit/normal_smoothing.h"
#include "libs/synth/gbuffer.h"
#include "libs/synth/ray_scene.h"
#include "core/util/error.h"
#include "core/util/cpu_time.h"

namespace facetool {

namespace {
double since(double start) { return thread_cpu_seconds() - start; }
}  // namespace

FaceMesh fitted_mesh(const FaceModel& model, const FaceFit& fit) {
  ShapeWeights weights;
  weights.identity.assign(fit.identity.begin(), fit.identity.end());
  weights.expression.assign(fit.expression.begin(), fit.expression.end());
  FaceMesh mesh = model.build(weights);
  for (Vec3f& p : mesh.positions) p = fit.to_camera(p);
  return mesh;
}

double fitted_eye_distance_px(const FaceFit& fit, const FaceMesh& mesh) {
  const Point2 a = fit.project(mesh.positions.at(fit.vertices[36]));
  const Point2 b = fit.project(mesh.positions.at(fit.vertices[45]));
  return std::hypot(a.x - b.x, a.y - b.y);
}

FitRendering render_fit(const FaceModel& model, const FaceFit& fit, const VisibilitySampler* sampler,
                        const FitRenderSettings& settings) {
  check(fit.width > 0 && fit.height > 0, "render_fit: the fit has no photo size");
  check(!settings.visibility || sampler != nullptr, "render_fit: visibility needs a sampler");
  const double start = thread_cpu_seconds();
  FitRendering out;
  out.width = fit.width;
  out.height = fit.height;
  out.mesh = fitted_mesh(model, fit);
  const std::vector<Vec3f> normals = vertex_normals(out.mesh);
  const RayScene scene(out.mesh.positions, out.mesh.triangles);
  float front = -1e30f;
  Vec3f low{1e30f, 1e30f, 1e30f}, high{-1e30f, -1e30f, -1e30f};
  for (int32_t v : out.mesh.fit_vertices) {
    const Vec3f p = out.mesh.positions[v];
    front = std::max(front, p.z);
    for (int c = 0; c < 3; ++c) {
      low[c] = std::min(low[c], p[c]);
      high[c] = std::max(high[c], p[c]);
    }
  }
  // Only the pixels the mesh's projection can reach are cast (a face is a small part of most photos).
  double px0 = 1e30, py0 = 1e30, px1 = -1e30, py1 = -1e30;
  for (const Vec3f& p : out.mesh.positions) {
    front = std::max(front, p.z);
    if (fit.camera == FitCamera::kPerspective && p.z > -1e-6f) {  // behind the camera: cast everything
      px0 = py0 = -1e30;
      px1 = py1 = 1e30;
      continue;
    }
    const Point2 q = fit.project(p);
    px0 = std::min(px0, q.x);
    py0 = std::min(py0, q.y);
    px1 = std::max(px1, q.x);
    py1 = std::max(py1, q.y);
  }
  auto clamp_to = [](double v, int hi) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(hi))); };
  const PixelRect rect{clamp_to(std::floor(px0) - 1, fit.width), clamp_to(std::floor(py0) - 1, fit.height),
                       clamp_to(std::ceil(px1) + 2, fit.width), clamp_to(std::ceil(py1) + 2, fit.height)};
  GBuffer g;
  if (fit.camera == FitCamera::kScaledOrthographic) {
    // Parallel rays down -Z from in front of the mesh; depth from the plane z = 0.
    const float origin_z = front + 1.0f + 0.01f * (high.x - low.x);
    g = cast_rays(scene, out.mesh, normals, fit.width, fit.height, 0.0f,
                  [&](int x, int y, Vec3f& origin, Vec3f& direction) {
                    origin = {static_cast<float>(x - fit.cx), static_cast<float>(fit.cy - y), origin_z};
                    direction = {0.0f, 0.0f, -1.0f};
                  },
                  rect);
  } else {
    const float inv_f = static_cast<float>(1.0 / fit.focal_px);
    g = cast_rays(scene, out.mesh, normals, fit.width, fit.height, 0.0f,
                  [&](int x, int y, Vec3f& origin, Vec3f& direction) {
                    origin = {0.0f, 0.0f, 0.0f};
                    direction = normalized(Vec3f{static_cast<float>(x - fit.cx) * inv_f,
                                                 static_cast<float>(fit.cy - y) * inv_f, -1.0f});
                  },
                  rect);
  }
  const size_t plane = static_cast<size_t>(fit.width) * fit.height;
  out.head = g.head;
  out.mask = g.mask;
  out.reference = g.reference;
  out.normal.assign(3 * plane, 0.0f);
  out.depth.assign(plane, 0.0f);
  for (size_t p = 0; p < plane; ++p) {
    if (!g.head[p]) continue;
    for (int c = 0; c < 3; ++c) out.normal[c * plane + p] = g.normal[p][c];
    out.depth[p] = g.depth[p];
  }
  if (settings.normal_smoothing != 0)
    smooth_normals(out.normal, out.head, fit.width, fit.height,
                   settings.normal_smoothing * fitted_eye_distance_px(fit, out.mesh));
  out.seconds_geometry = since(start);
  if (settings.visibility) {
    const double visibility_start = thread_cpu_seconds();
    std::vector<uint8_t> domain = dilate_mask(g.mask, fit.width, fit.height);
    for (size_t p = 0; p < plane; ++p) domain[p] = domain[p] && g.head[p];
    const float size = std::max({high.x - low.x, high.y - low.y, high.z - low.z});
    out.rays_cast = integrate_visibility_image(*sampler, scene, g.position, g.normal, domain, fit.width,
                                               fit.height, settings.ray_offset_fraction * size, out.visibility);
    out.seconds_visibility = since(visibility_start);
  } else {
    out.visibility.assign(9 * plane, 0.0f);
  }
  return out;
}

}  // namespace facetool
