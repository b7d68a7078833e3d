// FitBasis: the rows of the ICT face model a landmark fit needs (mean and shape modes of the 68
// landmark vertices and of the jaw's contour candidates), taken from a loaded FaceModel.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libs/synth/face_model.h"

namespace facetool {

class FitBasis {
 public:
  // Throws facetool::Error when the model has no 68 landmark vertices.
  explicit FitBasis(std::shared_ptr<const FaceModel> model);
  // The same with other vertices for the 68 landmarks (kept-vertex indices), e.g. to measure a
  // correspondence other than the model's vertex_indices.json.
  FitBasis(std::shared_ptr<const FaceModel> model, const std::array<int32_t, 68>& landmark_vertices);
  // FaceModel::load(directory), then the basis.
  static FitBasis load(const std::string& face_model_directory);

  const FaceModel& model() const { return *model_; }
  std::shared_ptr<const FaceModel> model_ptr() const { return model_; }
  int identity_count() const { return identity_count_; }
  int expression_count() const { return expression_count_; }
  // Doubles per vertex row: 3 coordinates x (1 mean + identities + expressions).
  int row_stride() const { return 1 + identity_count_ + expression_count_; }

  // The 68 landmark vertices (kept-vertex indices of the model).
  const std::array<int32_t, 68>& landmark_vertices() const { return landmark_vertices_; }
  // Candidate silhouette vertices of jaw landmark j (0..16; empty for the chin, 8): face-region
  // vertices on the same side at about the same height, from the landmark outwards to the ear.
  const std::vector<int32_t>& contour_candidates(int j) const { return contour_candidates_[j]; }

  // Row of vertex v: [3][row_stride()], coordinate-major (x: mean, identity 0.., expression 0..).
  // Only landmark vertices and contour candidates have rows (others throw).
  const double* row(int32_t vertex) const;
  // Neutral vertex normal (model frame) of a vertex with a row.
  const Vec3f& neutral_normal(int32_t vertex) const;

 private:
  std::shared_ptr<const FaceModel> model_;
  int identity_count_ = 0, expression_count_ = 0;
  std::array<int32_t, 68> landmark_vertices_{};
  std::array<std::vector<int32_t>, 17> contour_candidates_;
  std::vector<int32_t> row_of_vertex_;  // -1: no row
  std::vector<double> rows_;
  std::vector<Vec3f> normals_;          // per row
};

}  // namespace facetool
