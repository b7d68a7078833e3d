// Vertex normals and loading of user meshes.
#include "libs/synth/face_mesh.h"

#include <cmath>
#include <numeric>
#include <utility>

#include "libs/io/obj_reader.h"
#include "core/util/error.h"

namespace facetool {

std::vector<Vec3f> vertex_normals(const FaceMesh& mesh) {
  std::vector<Vec3f> normals(mesh.positions.size());
  for (const auto& t : mesh.triangles) {
    const Vec3f a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    const Vec3f weighted = cross(b - a, c - a);  // length = twice the area
    for (int k = 0; k < 3; ++k) normals[t[k]] += weighted;
  }
  for (Vec3f& n : normals) n = normalized(n);
  return normals;
}

Vec3f fit_sphere_centre(const std::vector<Vec3f>& points) {
  double m[4][5] = {};
  for (const Vec3f& p : points) {
    const double row[4] = {2.0 * p.x, 2.0 * p.y, 2.0 * p.z, 1.0};
    const double rhs = static_cast<double>(p.x) * p.x + static_cast<double>(p.y) * p.y +
                       static_cast<double>(p.z) * p.z;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) m[i][j] += row[i] * row[j];
      m[i][4] += row[i] * rhs;
    }
  }
  for (int i = 0; i < 4; ++i) {  // Gauss-Jordan with partial pivoting
    int pivot = i;
    for (int r = i + 1; r < 4; ++r)
      if (std::fabs(m[r][i]) > std::fabs(m[pivot][i])) pivot = r;
    std::swap(m[i], m[pivot]);
    if (std::fabs(m[i][i]) < 1e-12) return points.empty() ? Vec3f{} : points[0];
    for (int r = 0; r < 4; ++r) {
      if (r == i) continue;
      const double f = m[r][i] / m[i][i];
      for (int j = i; j < 5; ++j) m[r][j] -= f * m[i][j];
    }
  }
  return {static_cast<float>(m[0][4] / m[0][0]), static_cast<float>(m[1][4] / m[1][1]),
          static_cast<float>(m[2][4] / m[2][2])};
}

FaceMesh load_user_mesh(const std::string& obj_path) {
  ObjMesh obj = read_obj(obj_path);
  check(!obj.triangles.empty(), "mesh '", obj_path,
        "' has no faces (f lines); --mesh needs a triangle or polygon mesh");
  FaceMesh mesh;
  mesh.positions.reserve(obj.positions.size());
  for (const auto& p : obj.positions) mesh.positions.push_back({p[0], p[1], p[2]});
  mesh.triangles = std::move(obj.triangles);
  mesh.triangle_parts.assign(mesh.triangles.size(), FacePart::kOther);
  mesh.reference_positions = mesh.positions;
  mesh.fit_vertices.resize(mesh.positions.size());
  std::iota(mesh.fit_vertices.begin(), mesh.fit_vertices.end(), 0);
  return mesh;
}

}  // namespace facetool
