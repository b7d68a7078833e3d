// FaceDetector on dlib: HOG detection on a scaled grey copy, shape prediction at full size.
#include "core/face/face_detector.h"

#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_transforms.h>
#include <dlib/serialize.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "core/util/error.h"
#include "core/util/stage_timer.h"

namespace facetool {

const char* const kDefaultLandmarkModel = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// sRGB-encoded 8-bit luma (Rec. 709 weights on the linear values), what dlib's models expect.
void to_grey(const RgbImage& photo, dlib::array2d<unsigned char>& grey) {
  grey.set_size(photo.height, photo.width);
  for (int y = 0; y < photo.height; ++y)
    for (int x = 0; x < photo.width; ++x) {
      const float* p = photo.at(x, y);
      const float luma = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
      grey[y][x] = static_cast<unsigned char>(std::lround(linear_to_srgb(luma) * 255.0f));
    }
}

Landmarks68 to_landmarks(const dlib::full_object_detection& shape) {
  check(shape.num_parts() == kLandmarkCount, "the landmark model gives ", shape.num_parts(),
        " points; facetool needs a 68-point model");
  Landmarks68 out;
  for (int i = 0; i < kLandmarkCount; ++i)
    out[i] = {static_cast<double>(shape.part(i).x()), static_cast<double>(shape.part(i).y())};
  return out;
}

}  // namespace

struct FaceDetector::Impl {
  dlib::frontal_face_detector detector = dlib::get_frontal_face_detector();
  dlib::shape_predictor predictor;
};

FaceDetector::FaceDetector(const std::string& landmark_model) : impl_(std::make_unique<Impl>()) {
  check(std::filesystem::is_regular_file(landmark_model), "landmark model '", landmark_model,
        "' not found: install Debian's libdlib-data (scripts/install-dependencies.sh) or pass "
        "--landmark-model FILE");
  StageTimer timer("load models");
  try {
    dlib::deserialize(landmark_model) >> impl_->predictor;
  } catch (const std::exception& e) {
    fail("cannot read landmark model '", landmark_model, "': ", e.what(),
         " (expected dlib's shape_predictor_68_face_landmarks.dat)");
  }
  check(impl_->predictor.num_parts() == kLandmarkCount, "landmark model '", landmark_model,
        "' predicts ", impl_->predictor.num_parts(), " points; facetool needs the 68-point model");
}

FaceDetector::~FaceDetector() = default;

namespace {

// The shape predictor is most accurate on upright faces: when the eye line of a first fit is
// tilted by more than kRefitRollDeg, fit again on a chip of the photo turned upright around the
// face and map the points back.
constexpr double kRefitRollDeg = 8;

void refit_upright(const dlib::shape_predictor& predictor, const dlib::array2d<unsigned char>& grey,
                   DetectedFace& face) {
  Point2 left, right;
  for (int i = 36; i < 42; ++i) {
    left.x += face.landmarks[i].x / 6;
    left.y += face.landmarks[i].y / 6;
    right.x += face.landmarks[i + 6].x / 6;
    right.y += face.landmarks[i + 6].y / 6;
  }
  const double roll = std::atan2(right.y - left.y, right.x - left.x);
  if (std::abs(roll) < kRefitRollDeg * 3.14159265358979323846 / 180) return;
  const double cx = (face.left + face.right) / 2, cy = (face.top + face.bottom) / 2;
  const double box = face.size();
  const long chip = std::clamp(std::lround(2 * box), 64L, 800L);  // the box plus a margin
  const dlib::chip_details details(dlib::centered_drect(dlib::dpoint(cx, cy), 2 * box, 2 * box),
                                   dlib::chip_dims(chip, chip), roll);
  dlib::array2d<unsigned char> upright;
  dlib::extract_image_chip(grey, details, upright);
  const long quarter = chip / 4;
  const dlib::full_object_detection shape =
      predictor(upright, dlib::rectangle(quarter, quarter, chip - quarter, chip - quarter));
  const dlib::point_transform_affine back = dlib::inv(dlib::get_mapping_to_chip(details));
  for (int i = 0; i < kLandmarkCount; ++i) {
    const dlib::dpoint q = back(dlib::dpoint(shape.part(i).x(), shape.part(i).y()));
    face.landmarks[i] = {q.x(), q.y()};
  }
}

// Upright faces of `grey`, best first; adds the time spent to the two counters.
std::vector<DetectedFace> detect_upright(dlib::frontal_face_detector& detector,
                                         const dlib::shape_predictor& predictor,
                                         const dlib::array2d<unsigned char>& grey,
                                         const DetectionOptions& options,
                                         double& detection_seconds, double& landmark_seconds) {
  const auto start = Clock::now();
  const long width = grey.nc(), height = grey.nr();
  const double min_size = options.min_face_size > 0
                              ? options.min_face_size
                              : std::max(80.0, std::min(width, height) / 8.0);
  const double scale = std::min(4.0, 80.0 / min_size);  // the HOG window is 80 x 80
  std::vector<dlib::rect_detection> found;
  if (std::abs(scale - 1.0) < 1e-6) {
    detector(grey, found, options.score_threshold);
  } else {
    dlib::array2d<unsigned char> scaled(std::max(1L, std::lround(height * scale)),
                                        std::max(1L, std::lround(width * scale)));
    dlib::resize_image(grey, scaled, dlib::interpolate_bilinear());
    detector(scaled, found, options.score_threshold);
    for (dlib::rect_detection& d : found)
      d.rect = dlib::rectangle(std::lround(d.rect.left() / scale), std::lround(d.rect.top() / scale),
                               std::lround(d.rect.right() / scale),
                               std::lround(d.rect.bottom() / scale));
  }
  std::sort(found.begin(), found.end(), [](const dlib::rect_detection& a,
                                            const dlib::rect_detection& b) {
    return a.detection_confidence > b.detection_confidence;
  });
  detection_seconds += seconds_since(start);

  const auto landmark_start = Clock::now();
  std::vector<DetectedFace> faces;
  for (const dlib::rect_detection& d : found) {
    if (options.max_faces > 0 && static_cast<int>(faces.size()) >= options.max_faces) break;
    DetectedFace face;
    face.left = d.rect.left();
    face.top = d.rect.top();
    face.right = d.rect.right();
    face.bottom = d.rect.bottom();
    face.score = d.detection_confidence;
    if (face.size() < min_size * 0.8) continue;  // the scaled detector's window allows ~20% less
    face.landmarks = to_landmarks(predictor(grey, d.rect));
    refit_upright(predictor, grey, face);
    faces.push_back(face);
  }
  landmark_seconds += seconds_since(landmark_start);
  return faces;
}

}  // namespace

std::vector<DetectedFace> FaceDetector::detect(const RgbImage& photo,
                                               const DetectionOptions& options) {
  check(photo.width > 0 && photo.height > 0, "face detection: the photo is empty");
  const auto whole_start = Clock::now();
  detection_seconds_ = landmark_seconds_ = 0;
  dlib::array2d<unsigned char> grey;
  to_grey(photo, grey);
  std::vector<DetectedFace> faces = detect_upright(impl_->detector, impl_->predictor, grey, options, detection_seconds_, landmark_seconds_);
  for (double degrees : options.fallback_rotations_deg) {
    if (!faces.empty()) break;
    // The HOG detector and the shape predictor want upright faces: turn the photo, detect,
    // and map the boxes and landmarks back.
    const auto start = Clock::now();
    dlib::array2d<unsigned char> turned;
    const dlib::point_transform_affine to_turned =
        dlib::rotate_image(grey, turned, degrees * 3.14159265358979323846 / 180.0,
                           dlib::interpolate_bilinear());
    const dlib::point_transform_affine back = dlib::inv(to_turned);
    detection_seconds_ += seconds_since(start);
    faces = detect_upright(impl_->detector, impl_->predictor, turned, options, detection_seconds_, landmark_seconds_);
    for (DetectedFace& face : faces) {
      for (Point2& p : face.landmarks) {
        const dlib::dpoint q = back(dlib::dpoint(p.x, p.y));
        p = {q.x(), q.y()};
      }
      double lx = 1e300, ly = 1e300, hx = -1e300, hy = -1e300;
      for (double x : {face.left, face.right})
        for (double y : {face.top, face.bottom}) {
          const dlib::dpoint q = back(dlib::dpoint(x, y));
          lx = std::min(lx, q.x());
          ly = std::min(ly, q.y());
          hx = std::max(hx, q.x());
          hy = std::max(hy, q.y());
        }
      face.left = lx;
      face.top = ly;
      face.right = hx;
      face.bottom = hy;
      face.rotation_deg = degrees;
    }
  }
  if (stage_timing_enabled()) {  // grey conversion and turning count as detection
    add_stage_time("landmarks", landmark_seconds_);
    add_stage_time("detect", seconds_since(whole_start) - landmark_seconds_);
  }
  return faces;
}


Landmarks68 FaceDetector::landmarks_in_box(const RgbImage& photo, double left, double top,
                                           double right, double bottom) {
  dlib::array2d<unsigned char> grey;
  to_grey(photo, grey);
  return to_landmarks(impl_->predictor(
      grey, dlib::rectangle(std::lround(left), std::lround(top), std::lround(right),
                            std::lround(bottom))));
}

}  // namespace facetool
