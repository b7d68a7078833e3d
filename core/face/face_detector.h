// FaceDetector: every face in a photo with its detection score and 68 landmarks (dlib's HOG
// frontal face detector and its 68-point shape predictor; dlib stays inside the .cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/face/point2.h"
#include "core/io/image_io.h"

namespace facetool {

// Debian libdlib-data's model; its training data (iBUG 300-W) excludes commercial use.
extern const char* const kDefaultLandmarkModel;

struct DetectedFace {
  double left = 0, top = 0, right = 0, bottom = 0;  // detector box, photo pixels
  double score = 0;                                  // HOG detector margin (> 0: a face)
  Landmarks68 landmarks{};                           // photo pixels
  double rotation_deg = 0;  // the photo turn it was found at (fallback_rotations_deg), or 0
  double size() const { return std::max(right - left, bottom - top); }
};

struct DetectionOptions {
  int max_faces = 0;            // keep the best-scoring this many (0: all)
  double min_face_size = 0;     // photo pixels; 0: automatic, max(80, shorter side / 8)
  double score_threshold = 0.25;  // detector margin below which a box is not a face
  // When the upright photo has no face, the photo turned by these angles (degrees, counter-
  // clockwise on screen) is searched in turn until one has; the HOG detector finds only
  // roughly upright faces (about +-20 degrees of roll).
  std::vector<double> fallback_rotations_deg = {-30, 30, -90, 90, 180};
};

class FaceDetector {
 public:
  // Loads the landmark model (about one second); throws facetool::Error naming the file and
  // the Debian package when it is missing or unreadable.
  explicit FaceDetector(const std::string& landmark_model = kDefaultLandmarkModel);
  ~FaceDetector();
  FaceDetector(const FaceDetector&) = delete;
  FaceDetector& operator=(const FaceDetector&) = delete;

  // Faces of `photo` (linear RGB; converted to sRGB grey for dlib), best score first. The
  // detector runs on the photo scaled so that `min_face_size` becomes dlib's 80-pixel window
  // (faster on big photos); landmarks are fitted at full resolution.
  std::vector<DetectedFace> detect(const RgbImage& photo, const DetectionOptions& options = {});
  // Landmarks only, in a given box (photo pixels): for tests on rendered faces with known boxes.
  Landmarks68 landmarks_in_box(const RgbImage& photo, double left, double top, double right,
                               double bottom);

  // Seconds the last detect() spent in detection and in the landmark fit (for benchmarks).
  double last_detection_seconds() const { return detection_seconds_; }
  double last_landmark_seconds() const { return landmark_seconds_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double detection_seconds_ = 0, landmark_seconds_ = 0;
};

}  // namespace facetool
