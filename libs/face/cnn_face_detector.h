// CnnFaceDetector: dlib's MMOD convolutional face detector (mmod_human_face_detector.dat) on
// 8-bit sRGB images; dlib stays inside the .cpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "libs/face/detection_bands.h"

namespace facetool {

// Where scripts/install-dependencies.sh puts the model: beside libdlib-data's landmark model.
extern const char* const kDefaultCnnFaceModel;

// Interleaved 8-bit sRGB, what dlib's networks expect.
struct Srgb8Image {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;  // [height][width][3]
};

// Who runs the network: facetool's convolutions (the cpu backend's fused path; the default),
// or dlib's own forward pass, the reference they are tested against (the same boxes; scores
// within float rounding).
enum class CnnForward { facetool, dlib };

class CnnFaceDetector {
 public:
  // Reads the model; throws facetool::Error naming the file (missing, not a regular file, or
  // not dlib's MMOD face detector) and saying how to get it or how to do without it.
  explicit CnnFaceDetector(const std::string& model = kDefaultCnnFaceModel);
  ~CnnFaceDetector();
  CnnFaceDetector(const CnnFaceDetector&) = delete;
  CnnFaceDetector& operator=(const CnnFaceDetector&) = delete;

  // The net's sliding window, image pixels (80 x 80 for dlib's model): a face is found at the
  // image's scale and at every level of the net's 5/6 image pyramid below it.
  int window_size() const;
  // Faces of `image` whose score exceeds `score_threshold` (0: the model's own threshold), best
  // first, boxes in image pixels.
  std::vector<ScoredBox> detect(const Srgb8Image& image, double score_threshold = 0) const;
  void set_forward(CnnForward forward) { forward_ = forward; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  CnnForward forward_ = CnnForward::facetool;
};

}  // namespace facetool
