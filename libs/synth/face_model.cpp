// Loading the ICT Face Model from a folder and drawing random identities and expressions.
#include "libs/synth/face_model.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "libs/io/obj_reader.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/math_constants.h"

namespace facetool {
namespace fs = std::filesystem;

const char* const kIctFaceKitHint =
    "get the ICT Face Model (MIT licence) from https://github.com/ICT-VGL/ICT-FaceKit and pass "
    "its FaceXModel folder with --face-model DIR, or render your own mesh with --mesh FILE.obj";

namespace {

const char kNeutralFile[] = "generic_neutral_mesh.obj";

// "identity007.obj" -> 7; -1 for other names.
int identity_number(const std::string& file_name) {
  const std::string prefix = "identity";
  if (file_name.rfind(prefix, 0) != 0 || file_name.size() <= prefix.size() + 4) return -1;
  const std::string digits = file_name.substr(prefix.size(), file_name.size() - prefix.size() - 4);
  if (digits.empty() || !std::all_of(digits.begin(), digits.end(), ::isdigit)) return -1;
  int number = -1;
  const auto [after, status] = std::from_chars(digits.data(), digits.data() + digits.size(), number);
  return status == std::errc() && after == digits.data() + digits.size() ? number : -1;
}

// The integer list after "idx_to_landmark_verts" in vertex_indices.json (no JSON library
// needed for one flat array); empty when the file or key is absent.
std::vector<int32_t> read_landmark_vertices(const fs::path& json_path) {
  std::error_code error;
  if (!fs::exists(json_path, error)) return {};
  const std::string text =
      read_regular_input_file(json_path.string(), kMaxTextFileBytes, "ICT landmark file");
  const size_t key = text.find("\"idx_to_landmark_verts\"");
  if (key == std::string::npos) return {};
  const size_t open = text.find('[', key), close = text.find(']', key);
  check(open != std::string::npos && close != std::string::npos && open < close,
        "face model file '", json_path.string(), "': malformed idx_to_landmark_verts list");
  std::vector<int32_t> values;
  std::stringstream list(text.substr(open + 1, close - open - 1));
  std::string item;
  while (std::getline(list, item, ',')) {
    const size_t first = item.find_first_not_of(" \t\r\n"), last = item.find_last_not_of(" \t\r\n");
    const std::string number = first == std::string::npos ? std::string() : item.substr(first, last - first + 1);
    errno = 0;
    char* end = nullptr;
    const long value = std::strtol(number.c_str(), &end, 10);
    check(!number.empty() && *end == '\0' && errno == 0 && value >= 0 && value < (1L << 30), "face model file '",
          json_path.string(), "': item ", values.size(), " of idx_to_landmark_verts ('", number.substr(0, 40),
          "') is not a vertex index; use the ICT Face Model's own vertex_indices.json");
    values.push_back(static_cast<int32_t>(value));
  }
  return values;
}

// Every vertex of a face model mesh finite (a NaN would reach the fit and the renders unseen).
void check_finite_positions(const ObjMesh& mesh, const fs::path& path) {
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    for (int k = 0; k < 3; ++k)
      check(std::isfinite(mesh.positions[v][k]), "face model mesh '", path.string(), "': vertex ", v + 1,
            " (its 'v' line, counted from 1) is not finite; use the ICT Face Model's own files");
}

// Offsets (file - neutral) of the kept vertices, from a shape file with the neutral's topology.
std::vector<Vec3f> read_shape_mode(const fs::path& path, const ObjMesh& neutral,
                                   const std::vector<int32_t>& kept_vertices) {
  const ObjMesh shape = read_obj(path.string());
  check(shape.positions.size() == neutral.positions.size(), "face model shape file '",
        path.string(), "' has ", shape.positions.size(), " vertices but the neutral mesh has ",
        neutral.positions.size(), "; every shape must come from the same ICT Face Model");
  check_finite_positions(shape, path);
  std::vector<Vec3f> mode(kept_vertices.size());
  for (size_t k = 0; k < kept_vertices.size(); ++k) {
    const auto& s = shape.positions[kept_vertices[k]];
    const auto& n = neutral.positions[kept_vertices[k]];
    mode[k] = {s[0] - n[0], s[1] - n[1], s[2] - n[2]};
  }
  return mode;
}

// The outer eyeball shells (kSclera) cover the irises: their front caps, within
// kCorneaHalfAngleDeg of +Z (the neutral face's gaze) seen from each shell's fitted centre,
// are the clear cornea and become kCornea.
constexpr double kCorneaHalfAngleDeg = 30.0;
void mark_corneas(const ObjMesh& mesh, std::vector<FacePart>& parts) {
  for (int side = 0; side < 2; ++side) {
    auto on_side = [&](size_t t) {
      const auto& p = mesh.positions[mesh.triangles[t][0]];
      return parts[t] == FacePart::kSclera && (p[0] >= 0) == (side == 0);
    };
    std::vector<Vec3f> points;
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      if (on_side(t))
        for (int32_t v : mesh.triangles[t])
          points.push_back({mesh.positions[v][0], mesh.positions[v][1], mesh.positions[v][2]});
    if (points.size() < 4) continue;
    const Vec3f centre = fit_sphere_centre(points);
    const float cos_limit = static_cast<float>(std::cos(kCorneaHalfAngleDeg * kPi / 180.0));
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (!on_side(t)) continue;
      Vec3f centroid{};
      for (int32_t v : mesh.triangles[t])
        centroid += Vec3f{mesh.positions[v][0], mesh.positions[v][1], mesh.positions[v][2]} * (1.0f / 3.0f);
      if (normalized(centroid - centre).z > cos_limit) parts[t] = FacePart::kCornea;
    }
  }
}

}  // namespace

FaceModel FaceModel::load(const std::string& directory) {
  const fs::path dir(directory);
  check(fs::is_directory(dir), "face model folder '", directory, "' does not exist: ",
        kIctFaceKitHint);
  const fs::path neutral_path = dir / kNeutralFile;
  check(fs::is_regular_file(neutral_path), "face model folder '", directory, "' has no ",
        kNeutralFile, ": ", kIctFaceKitHint);
  const ObjMesh neutral = read_obj(neutral_path.string());
  check_finite_positions(neutral, neutral_path);
  check(!neutral.triangles.empty(), "face model mesh '", neutral_path.string(),
        "' has no faces: use the full generic_neutral_mesh.obj of the ICT Face Model (",
        kIctFaceKitHint, ")");
  const bool layout_known =
      static_cast<int32_t>(neutral.positions.size()) == IctVertexLayout::kVertexCount;

  // Classify polygons (per triangle), cut the cornea out of the outer eyeball shells, then keep
  // the wanted parts and compact the vertices they use.
  std::vector<FacePart> parts(neutral.triangles.size(), FacePart::kOther);
  std::vector<int32_t> corners;
  for (size_t t = 0; t < neutral.triangles.size();) {
    // A polygon's triangles are consecutive: gather all its corners to classify it.
    const int32_t polygon = neutral.triangle_polygon[t];
    size_t end = t;
    corners.clear();
    for (; end < neutral.triangles.size() && neutral.triangle_polygon[end] == polygon; ++end)
      for (int32_t v : neutral.triangles[end]) corners.push_back(v);
    const int32_t material = neutral.triangle_material[t];
    const FacePart part =
        classify_ict_polygon(material >= 0 ? neutral.materials[material] : std::string(),
                             corners.data(), static_cast<int>(corners.size()), layout_known);
    for (; t < end; ++t) parts[t] = part;
  }
  mark_corneas(neutral, parts);

  std::vector<int32_t> new_index(neutral.positions.size(), -1);
  std::vector<int32_t> kept_vertices;
  FaceModel model;
  FaceMesh& mesh = model.neutral_;
  for (size_t t = 0; t < neutral.triangles.size(); ++t) {
    if (!is_kept_part(parts[t])) continue;
    std::array<int32_t, 3> triangle{};
    for (int k = 0; k < 3; ++k) {
      const int32_t v = neutral.triangles[t][k];
      if (new_index[v] < 0) {
        new_index[v] = static_cast<int32_t>(kept_vertices.size());
        kept_vertices.push_back(v);
      }
      triangle[k] = new_index[v];
    }
    mesh.triangles.push_back(triangle);
    mesh.triangle_parts.push_back(parts[t]);
  }
  for (int32_t v : kept_vertices) {
    const auto& p = neutral.positions[v];
    mesh.positions.push_back({p[0], p[1], p[2]});
  }
  mesh.reference_positions = mesh.positions;
  for (size_t k = 0; k < kept_vertices.size(); ++k)
    if (!layout_known || kept_vertices[k] < IctVertexLayout::kFaceRegionEnd)
      mesh.fit_vertices.push_back(static_cast<int32_t>(k));

  // Shape modes: identities in numeric order, then expressions by name.
  std::map<int, fs::path> identity_files;
  std::map<std::string, fs::path> expression_files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".obj") continue;
    const std::string name = entry.path().filename().string();
    if (name == kNeutralFile) continue;
    const int number = identity_number(name);
    if (number >= 0)
      identity_files[number] = entry.path();
    else
      expression_files[entry.path().stem().string()] = entry.path();
  }
  for (const auto& [number, path] : identity_files)
    model.identity_modes_.push_back(read_shape_mode(path, neutral, kept_vertices));
  for (const auto& [name, path] : expression_files) {
    model.expression_names_.push_back(name);
    model.expression_modes_.push_back(read_shape_mode(path, neutral, kept_vertices));
  }
  check(!identity_files.empty() && !expression_files.empty(), "face model folder '", directory, "' has ",
        identity_files.size(), " identity shape files (identityNNN.obj) and ", expression_files.size(),
        " expression shape files; the fit and synth need both: ", kIctFaceKitHint);

  for (int32_t v : read_landmark_vertices(dir / "vertex_indices.json")) {
    const bool valid = v >= 0 && v < static_cast<int32_t>(new_index.size());
    model.landmarks_.push_back(valid ? new_index[v] : -1);
  }
  return model;
}

FaceMesh FaceModel::build(const ShapeWeights& weights) const {
  check(weights.identity.size() == identity_modes_.size() &&
            weights.expression.size() == expression_modes_.size(),
        "face model: got ", weights.identity.size(), " identity and ", weights.expression.size(),
        " expression weights for a model with ", identity_modes_.size(), " and ",
        expression_modes_.size());
  FaceMesh mesh = neutral_;
  auto add = [&mesh](const std::vector<Vec3f>& mode, float weight) {
    if (weight == 0.0f) return;
    for (size_t v = 0; v < mode.size(); ++v) mesh.positions[v] += mode[v] * weight;
  };
  for (size_t k = 0; k < identity_modes_.size(); ++k) add(identity_modes_[k], weights.identity[k]);
  for (size_t k = 0; k < expression_modes_.size(); ++k)
    add(expression_modes_[k], weights.expression[k]);
  return mesh;
}

ShapeWeights FaceModel::sample(Random& random, const ShapeSampling& sampling) const {
  ShapeWeights weights;
  for (size_t k = 0; k < identity_modes_.size(); ++k)
    weights.identity.push_back(static_cast<float>(random.truncated_normal(sampling.identity_truncation)));
  weights.expression.assign(expression_modes_.size(), 0.0f);
  for (const auto& [name, weight] : sampling.fixed_expressions)
    check(std::find(expression_names_.begin(), expression_names_.end(), name) != expression_names_.end(),
          "expression '", name, "' is not in the face model (", expression_names_.size(),
          " expressions, e.g. eyeBlink_L, jawOpen)");
  if (!expression_modes_.empty() && sampling.max_active_expressions > 0) sample_random_expressions(random, sampling, weights);
  for (const auto& [name, weight] : sampling.fixed_expressions)
    for (size_t j = 0; j < expression_names_.size(); ++j)
      if (expression_names_[j] == name) weights.expression[j] = static_cast<float>(weight);
  return weights;
}

void FaceModel::sample_random_expressions(Random& random, const ShapeSampling& sampling,
                                          ShapeWeights& weights) const {
  const auto active = random.index(static_cast<uint64_t>(sampling.max_active_expressions) + 1);
  for (uint64_t a = 0; a < active; ++a) {
    const size_t k = random.index(expression_modes_.size());
    const float weight = static_cast<float>(random.uniform(0.0, sampling.max_expression_weight));
    weights.expression[k] = weight;
    // "_L" <-> "_R" twin, so smiles and blinks are often symmetric.
    const std::string& name = expression_names_[k];
    if (name.size() > 2 && name[name.size() - 2] == '_' && random.bernoulli(sampling.symmetric_probability)) {
      std::string twin = name;
      twin.back() = name.back() == 'L' ? 'R' : 'L';
      for (size_t j = 0; j < expression_names_.size(); ++j)
        if (expression_names_[j] == twin) weights.expression[j] = weight;
    }
  }
}

}  // namespace facetool
