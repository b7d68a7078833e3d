// The landmark normal head: a ridge regression from a crop's 68 landmarks to a coarse normal map, stored beside the network.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libs/model/safetensors.h"

namespace facetool {

// A linear map from features of the 68 landmarks (crop pixels; docs/model-card.md, "The landmark
// normal head") to a grid x grid map of four values per cell: the normal times the face mask
// (3) and the mask. Prediction upsamples the map bilinearly to the crop, normalises the normal
// and blends it into the network's normals where the mask holds (blend_into). It needs no face
// model at run time: it is fitted, once, to labelled real samples (fit_landmark_normals).
struct LandmarkNormals {
  static constexpr int kLandmarks = 68;
  // x and y of every point, centred and scaled by half the crop, then their squares, then 1.
  static constexpr int kFeatures = 4 * kLandmarks + 1;
  static constexpr int kValues = 4;  // normal.X/Y/Z times the mask, the mask

  int crop_size = 0;   // the crop it was fitted at (the network's input size)
  int grid = 0;        // cells per side; crop_size is a multiple of it
  float blend = 1.0f;  // the head's weight against the network's normals, in [0, 1]
  double lambda = 0;   // the ridge penalty it was fitted with (recorded only)
  std::vector<float> weights;  // [kFeatures][grid * grid * kValues]
  // The mean of the faces' landmarks it was fitted to ([68][2], crop pixels): a face is first
  // moved onto it by the similarity that best maps its 51 inner points there, so a rolled,
  // shifted or scaled face (a synthetic sample, an unaligned crop) is read as the aligned crops
  // it learnt from, and the prediction is turned back with it.
  std::vector<float> mean_landmarks;

  // The landmark features of one face: `xy` holds 68 (x, y) pairs in crop pixels (pixel
  // centres at whole numbers, as dlib's points).
  static std::vector<double> features(const float* xy, int crop_size);
  // The normal [3][S*S] (unit vectors where the mask is above 0, else 0) and the mask [S*S]
  // (clamped to [0, 1]) at the crop's resolution S = crop_size.
  void predict(const float* xy, std::vector<float>& normal, std::vector<float>& mask) const;
  // Blends the head's normals into `normal` ([3][S*S] unit vectors, the network's): where the
  // head's mask m is above 0.3, n = normalise(w h + (1 - w) n) with w = blend * min(1, (m - 0.3) / 0.4),
  // so the face's inside takes the head's weight and its edge fades to the network's. `mask_out`
  // (optional) receives the head's mask, as predict gives it.
  void blend_into(const float* xy, float* normal, std::vector<float>* mask_out = nullptr) const;
};

// Accumulates labelled faces, then solves the ridge regression (normal equations, Cholesky).
// Each face is first moved onto `mean_landmarks` ([68][2], crop pixels: the mean of the faces'
// landmarks, mean_landmarks below) by its similarity, its labels with it, as predict does.
class LandmarkNormalsFit {
 public:
  LandmarkNormalsFit(int crop_size, int grid, std::vector<float> mean_landmarks);
  // One face: its landmarks (68 (x, y) pairs, crop pixels), its normal label [3][S*S] and its
  // label mask [S*S] (values above 0.5 count as face), both at crop_size.
  void add(const float* xy, const float* normal, const float* mask);
  int64_t count() const { return count_; }
  // The head: minimises sum ||F W - Y||^2 + lambda ||W||^2 over the faces added.
  LandmarkNormals solve(double lambda, float blend) const;

 private:
  int crop_size_, grid_;
  int64_t count_ = 0;
  std::vector<double> gram_;    // [kFeatures][kFeatures]
  std::vector<double> moment_;  // [kFeatures][grid * grid * kValues]
  std::vector<float> mean_;
};

// The mean of faces' landmarks (`landmarks`: N x 68 (x, y) pairs), for LandmarkNormalsFit.
std::vector<float> mean_landmarks(const std::vector<float>& landmarks);

// The head stored in a weights file (tensors kLandmarkNormalsTensor and kLandmarkNormalsMean,
// metadata "landmark_normals"), or null when the file has none. Fails naming `path` when it is
// damaged.
std::shared_ptr<const LandmarkNormals> read_landmark_normals(const SafeTensors& file, const std::string& path);
void add_landmark_normals(SafeTensorsWriter& writer, const LandmarkNormals& head);
constexpr const char* kLandmarkNormalsTensor = "landmark_normals.weight";
constexpr const char* kLandmarkNormalsMean = "landmark_normals.mean_landmarks";
// Whether a weights file's tensor belongs to the head (not the network's).
bool is_landmark_normals_tensor(const std::string& name);

}  // namespace facetool
