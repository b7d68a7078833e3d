// Reading Wavefront OBJ meshes: positions, texture coordinates, polygons triangulated as fans.
#pragma once

#include <array>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace facetool {

// A triangle mesh read from an OBJ file. Polygons with n > 3 corners become n - 2 triangles
// (a fan from the first corner); every triangle remembers the polygon, material and group it
// came from. A file with only `v` lines (a shape mode stored as vertices) gives no triangles.
struct ObjMesh {
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 2>> texcoords;
  std::vector<std::array<int32_t, 3>> triangles;  // 0-based position indices
  // 0-based texcoord indices per triangle corner, -1 where the face gave none; one per triangle.
  std::vector<std::array<int32_t, 3>> triangle_texcoords;
  std::vector<int32_t> triangle_polygon;  // index of the source `f` line (0-based)
  std::vector<int32_t> triangle_material;  // index into `materials`, -1 before any usemtl
  std::vector<int32_t> triangle_group;     // index into `groups`, -1 before any g
  std::vector<std::string> materials;      // usemtl names, in order of first use
  std::vector<std::string> groups;         // g names, in order of first use
  int32_t polygon_count = 0;
};

// Reads `path`; throws facetool::Error naming the file (and line) when it cannot be opened or
// holds a malformed line or an index outside the vertex list.
ObjMesh read_obj(const std::string& path);
// Parses OBJ text; `source_name` names the text in error messages.
ObjMesh parse_obj(const std::string& text, const std::string& source_name);

}  // namespace facetool
