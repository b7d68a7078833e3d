// libFuzzer target: the OBJ reader (face model meshes) refuses malformed text with
// facetool::Error, and every mesh it accepts has indices inside its own lists.
#include <cstddef>
#include <cstdint>
#include <string>

#include "libs/io/obj_reader.h"
#include "core/util/error.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

bool inside(int32_t index, size_t count) { return index >= 0 && static_cast<size_t>(index) < count; }

void check_mesh(const facetool::ObjMesh& mesh) {
  using facetool::fuzz::require;
  const size_t n = mesh.triangles.size();
  require(mesh.triangle_texcoords.size() == n && mesh.triangle_polygon.size() == n &&
              mesh.triangle_material.size() == n && mesh.triangle_group.size() == n,
          "per-triangle lists differ in length");
  for (size_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      require(inside(mesh.triangles[t][k], mesh.positions.size()), "vertex index out of range");
      const int32_t tc = mesh.triangle_texcoords[t][k];
      require(tc == -1 || inside(tc, mesh.texcoords.size()), "texcoord index out of range");
    }
    require(inside(mesh.triangle_polygon[t], static_cast<size_t>(mesh.polygon_count)),
            "polygon index out of range");
    require(mesh.triangle_material[t] == -1 || inside(mesh.triangle_material[t], mesh.materials.size()),
            "material index out of range");
    require(mesh.triangle_group[t] == -1 || inside(mesh.triangle_group[t], mesh.groups.size()),
            "group index out of range");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    check_mesh(facetool::parse_obj(std::string(reinterpret_cast<const char*>(data), size),
                                   "fuzz input"));
  } catch (const facetool::Error&) {
  }
  return 0;
}
