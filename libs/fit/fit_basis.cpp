// Gathering the landmark and contour-candidate rows of the face model's shape modes.
#include "libs/fit/fit_basis.h"

#include <algorithm>
#include <cmath>

#include "libs/face/landmarks68.h"
#include "libs/synth/face_parts.h"
#include "core/util/error.h"

namespace facetool {

namespace {
// A contour candidate lies within this fraction of the face's height (chin to brow) of its
// landmark's height, on the landmark's side, at least half as far out as the landmark, and no
// further back than this fraction of the landmark's distance from the mid-plane (ear side).
constexpr float kBandFraction = 0.03f;
constexpr float kBackFraction = 0.8f;
}  // namespace

FitBasis FitBasis::load(const std::string& face_model_directory) {
  return FitBasis(std::make_shared<const FaceModel>(FaceModel::load(face_model_directory)));
}

namespace {
std::array<int32_t, 68> model_landmark_vertices(const FaceModel* model) {
  check(model != nullptr, "FitBasis: no face model");
  check(model->landmarks().size() == static_cast<size_t>(kLandmarkCount),
        "face model has no 68 landmark vertices (vertex_indices.json missing?): the fit needs them");
  std::array<int32_t, 68> vertices{};
  std::copy(model->landmarks().begin(), model->landmarks().end(), vertices.begin());
  return vertices;
}
}  // namespace

FitBasis::FitBasis(std::shared_ptr<const FaceModel> model)
    : FitBasis(model, model_landmark_vertices(model.get())) {}

FitBasis::FitBasis(std::shared_ptr<const FaceModel> model, const std::array<int32_t, 68>& landmark_vertices)
    : model_(std::move(model)), landmark_vertices_(landmark_vertices) {
  check(model_ != nullptr, "FitBasis: no face model");
  identity_count_ = model_->identity_count();
  expression_count_ = static_cast<int>(model_->expression_names().size());
  const FaceMesh& neutral = model_->neutral();
  for (int i = 0; i < kLandmarkCount; ++i)
    check(landmark_vertices_[i] >= 0 && static_cast<size_t>(landmark_vertices_[i]) < neutral.positions.size(),
          "face model: landmark ", i, " is not on a kept vertex");
  // Face-region vertices (of kFace triangles) are contour candidates.
  std::vector<uint8_t> is_face(neutral.positions.size(), 0);
  for (size_t t = 0; t < neutral.triangles.size(); ++t)
    if (neutral.triangle_parts[t] == FacePart::kFace)
      for (int32_t v : neutral.triangles[t]) is_face[v] = 1;
  const float face_height = neutral.positions[landmark_vertices_[27]].y - neutral.positions[landmark_vertices_[8]].y;
  const float band = kBandFraction * std::abs(face_height);
  for (int j = 0; j < 17; ++j) {
    if (j == 8) continue;  // the chin's outline faces down: its vertex stays fixed
    const Vec3f l = neutral.positions[landmark_vertices_[j]];
    for (size_t v = 0; v < neutral.positions.size(); ++v) {
      if (!is_face[v]) continue;
      const Vec3f p = neutral.positions[v];
      if (std::abs(p.y - l.y) > band || p.x * l.x <= 0 || std::abs(p.x) < 0.5f * std::abs(l.x)) continue;
      if (p.z < l.z - kBackFraction * std::abs(l.x)) continue;
      contour_candidates_[j].push_back(static_cast<int32_t>(v));
    }
    contour_candidates_[j].push_back(landmark_vertices_[j]);
    std::sort(contour_candidates_[j].begin(), contour_candidates_[j].end());
    contour_candidates_[j].erase(std::unique(contour_candidates_[j].begin(), contour_candidates_[j].end()),
                                 contour_candidates_[j].end());
  }

  row_of_vertex_.assign(neutral.positions.size(), -1);
  std::vector<int32_t> wanted(landmark_vertices_.begin(), landmark_vertices_.end());
  for (const auto& c : contour_candidates_) wanted.insert(wanted.end(), c.begin(), c.end());
  const std::vector<Vec3f> all_normals = vertex_normals(neutral);
  const int stride = row_stride();
  for (int32_t v : wanted) {
    if (row_of_vertex_[v] >= 0) continue;
    row_of_vertex_[v] = static_cast<int32_t>(normals_.size());
    normals_.push_back(all_normals[v]);
    const size_t base = rows_.size();
    rows_.resize(base + 3 * static_cast<size_t>(stride));
    for (int c = 0; c < 3; ++c) {
      double* r = &rows_[base + static_cast<size_t>(c) * stride];
      r[0] = neutral.positions[v][c];
      for (int k = 0; k < identity_count_; ++k) r[1 + k] = model_->identity_mode(k)[v][c];
      for (int e = 0; e < expression_count_; ++e)
        r[1 + identity_count_ + e] = model_->expression_mode(e)[v][c];
    }
  }
}

const double* FitBasis::row(int32_t vertex) const {
  check(vertex >= 0 && static_cast<size_t>(vertex) < row_of_vertex_.size() && row_of_vertex_[vertex] >= 0,
        "FitBasis: vertex ", vertex, " has no row");
  return &rows_[static_cast<size_t>(row_of_vertex_[vertex]) * 3 * row_stride()];
}

const Vec3f& FitBasis::neutral_normal(int32_t vertex) const {
  row(vertex);  // checks
  return normals_[row_of_vertex_[vertex]];
}

}  // namespace facetool
