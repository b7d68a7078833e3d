// FaceModel: the ICT Face Model (neutral mesh + identity and expression shape modes) loaded from
// a folder, restricted to the parts the generator keeps, and random shapes drawn from it.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "libs/synth/face_mesh.h"
#include "libs/synth/random.h"

namespace facetool {

// Where to get the model; quoted by every "face model missing" error.
extern const char* const kIctFaceKitHint;

// Weights of one random shape.
struct ShapeWeights {
  std::vector<float> identity;    // one per identity mode
  std::vector<float> expression;  // one per expression mode, in [0, max_weight]
};

struct ShapeSampling {
  double identity_truncation = 2.5;  // identity weights ~ N(0, 1) restricted to +-this
  int max_active_expressions = 4;    // 0..this expressions are active per sample
  double max_expression_weight = 1.0;
  double symmetric_probability = 0.5;  // an active _L/_R expression brings its twin along
  // Expressions set to a weight in every sample, after the random ones (synth --expression
  // eyeBlink_L=1): e.g. closed eyes for detector tests. A name the model lacks is an error.
  std::vector<std::pair<std::string, double>> fixed_expressions;
};

class FaceModel {
 public:
  // Reads DIR/generic_neutral_mesh.obj, DIR/identityNNN.obj (in numeric order) and every other
  // DIR/*.obj as an expression named after the file; DIR/vertex_indices.json (optional) gives
  // the 68 landmark vertices used by the albedo. Shape files may be full OBJ files or hold only
  // `v` lines; each must have the neutral mesh's vertex count. Throws facetool::Error with
  // kIctFaceKitHint when DIR or the neutral mesh is missing.
  static FaceModel load(const std::string& directory);

  int identity_count() const { return static_cast<int>(identity_modes_.size()); }
  const std::vector<std::string>& expression_names() const { return expression_names_; }
  // Landmark vertices (indices into the kept vertices; -1 where unknown), empty when the folder
  // had no vertex_indices.json.
  const std::vector<int32_t>& landmarks() const { return landmarks_; }
  // The neutral face (reference positions = positions).
  const FaceMesh& neutral() const { return neutral_; }
  // Offsets of shape mode k per kept vertex (what build() adds times its weight): for fitting.
  const std::vector<Vec3f>& identity_mode(int k) const { return identity_modes_[k]; }
  const std::vector<Vec3f>& expression_mode(int k) const { return expression_modes_[k]; }

  // neutral + sum w_k identity_k + sum e_k expression_k; the weights' sizes must match.
  FaceMesh build(const ShapeWeights& weights) const;
  ShapeWeights sample(Random& random, const ShapeSampling& sampling) const;

 private:
  void sample_random_expressions(Random& random, const ShapeSampling& sampling,
                                 ShapeWeights& weights) const;
  FaceMesh neutral_;
  std::vector<std::vector<Vec3f>> identity_modes_;    // per kept vertex offsets
  std::vector<std::vector<Vec3f>> expression_modes_;
  std::vector<std::string> expression_names_;
  std::vector<int32_t> landmarks_;
};

}  // namespace facetool
