// FaceMesh: a triangle mesh ready to pose and ray-cast, with per-triangle parts and per-vertex
// reference positions (where procedural albedo is evaluated, so it moves with the skin).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "libs/synth/face_parts.h"
#include "libs/synth/vec3.h"

namespace facetool {

struct FaceMesh {
  std::vector<Vec3f> positions;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<FacePart> triangle_parts;  // one per triangle
  // Position of each vertex on the undeformed neutral face (the albedo's coordinate system).
  std::vector<Vec3f> reference_positions;
  // Vertices whose bounding box is fitted into [-1, 1] when posing (the face region).
  std::vector<int32_t> fit_vertices;
};

// Area-weighted vertex normals (zero vectors for vertices of no triangle). Triangles are
// counter-clockwise seen from outside, so normals point out of the head.
std::vector<Vec3f> vertex_normals(const FaceMesh& mesh);

// Centre of the least-squares sphere through `points` (|p - c|^2 = r^2 solved linearly).
Vec3f fit_sphere_centre(const std::vector<Vec3f>& points);

// Loads a user's own mesh (e.g. a face scan) from an OBJ file: every triangle is kept as
// FacePart::kOther, all vertices are fitted, and the reference positions are the positions.
// Throws facetool::Error if it has no triangles.
FaceMesh load_user_mesh(const std::string& obj_path);

}  // namespace facetool
