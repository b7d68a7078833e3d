// Vertex normals and loading of user meshes.
#include "core/synth/face_mesh.h"

#include <numeric>

#include "core/io/obj_reader.h"
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
