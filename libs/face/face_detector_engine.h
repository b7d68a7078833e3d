// The interface of the face detector's dlib engine, compiled twice (face_detector_engine.cpp,
// portable; face_detector_engine_avx2.cpp, AVX2): FaceDetector holds one of the two.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "libs/face/face_detector.h"

namespace facetool {

class FaceDetectorEngine {
 public:
  virtual ~FaceDetectorEngine() = default;
  virtual void prepare(DetectorChoice choice) = 0;
  virtual std::vector<DetectedFace> detect(const RgbImage& photo, const DetectionOptions& options) = 0;
  virtual Landmarks68 landmarks_in_box(const RgbImage& photo, double left, double top, double right,
                                       double bottom) = 0;
  double detection_seconds = 0, landmark_seconds = 0;  // of the last detect()
};

// The engine in each compiled copy: loads the landmark model (throws facetool::Error naming it)
// and dlib's HOG detector; the CNN model is read on first use.
namespace portable {
std::unique_ptr<FaceDetectorEngine> make_face_detector_engine(const std::string& landmark_model,
                                                              const std::string& cnn_model);
// dlib's built-in HOG frontal face detector, decoded (about 0.3 s) and serialised: the fallback
// of both copies when the build's decoded copy is missing (hog_detector_copy_path()).
std::string builtin_hog_detector_bytes();
}
namespace avx2 {
std::unique_ptr<FaceDetectorEngine> make_face_detector_engine(const std::string& landmark_model,
                                                              const std::string& cnn_model);
}

}  // namespace facetool
