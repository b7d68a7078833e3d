// Synth test helpers.
#include "synth_test_support.h"
#include "core/util/math_constants.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace facetool::testing {
namespace fs = std::filesystem;

std::string shared_dir() {
  return fs::is_directory(FACETOOL_SHARED_DIR) ? std::string(FACETOOL_SHARED_DIR) : std::string();
}

std::string ict_face_model_dir() {
  const std::string dir = shared_dir() + "/assets/ict-facekit/FaceXModel";
  return !shared_dir().empty() && fs::is_directory(dir) ? dir : std::string();
}

std::string hdri_dir() {
  const std::string dir = shared_dir() + "/assets/hdri";
  return !shared_dir().empty() && fs::is_directory(dir) ? dir : std::string();
}

ScratchDir::ScratchDir(const std::string& name) {
  path_ = (fs::temp_directory_path() /
           ("facetool-" + name + "-" + std::to_string(static_cast<long>(::getpid()))))
              .string();
  fs::remove_all(path_);
  fs::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

FaceMesh make_sphere(int rings, int segments) {
  FaceMesh mesh;
  const double pi = kPi;
  mesh.positions.push_back({0, 1, 0});  // +Y pole
  for (int r = 1; r < rings; ++r) {
    const double theta = pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * pi * s / segments;
      mesh.positions.push_back({static_cast<float>(std::sin(theta) * std::cos(phi)),
                                static_cast<float>(std::cos(theta)),
                                static_cast<float>(-std::sin(theta) * std::sin(phi))});
    }
  }
  mesh.positions.push_back({0, -1, 0});
  const int bottom = static_cast<int>(mesh.positions.size()) - 1;
  auto ring_vertex = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    mesh.triangles.push_back({0, ring_vertex(1, s), ring_vertex(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r) {
      const int a = ring_vertex(r, s), b = ring_vertex(r, s + 1), c = ring_vertex(r + 1, s),
                d = ring_vertex(r + 1, s + 1);
      mesh.triangles.push_back({a, c, d});
      mesh.triangles.push_back({a, d, b});
    }
    mesh.triangles.push_back({ring_vertex(rings - 1, s), bottom, ring_vertex(rings - 1, s + 1)});
  }
  mesh.triangle_parts.assign(mesh.triangles.size(), FacePart::kOther);
  mesh.reference_positions = mesh.positions;
  for (int v = 0; v <= bottom; ++v) mesh.fit_vertices.push_back(v);
  return mesh;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

}  // namespace facetool::testing
