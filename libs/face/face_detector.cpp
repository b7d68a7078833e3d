// FaceDetector: the detector's options and reports, and the choice of its dlib engine (the
// AVX2 copy where the CPU has it, else the portable one; face_detector_engine.cpp).
#include "libs/face/face_detector.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "libs/face/face_detector_engine.h"
#include "core/util/error.h"
#include "core/util/memory_budget.h"
#include "core/util/shared_library.h"

namespace facetool {

const char* const kDefaultLandmarkModel = "/usr/share/dlib/shape_predictor_68_face_landmarks.dat";

const char* detector_choice_name(DetectorChoice choice) {
  switch (choice) {
    case DetectorChoice::hog: return "hog";
    case DetectorChoice::cnn: return "cnn";
    case DetectorChoice::automatic: return "auto";
  }
  return "?";
}

DetectorChoice parse_detector_choice(const std::string& name) {
  if (name == "hog") return DetectorChoice::hog;
  if (name == "cnn") return DetectorChoice::cnn;
  if (name == "auto") return DetectorChoice::automatic;
  fail("unknown face detector '", name, "': use hog, cnn or auto");
}

namespace {

// <program or libfacetool_core folder>/../share/facetool/dlib/<file_name> if it is a file, else "".
std::string build_copy_path(const char* file_name) {
  for (const std::string& base : {executable_dir(), core_library_dir()}) {
    if (base.empty()) continue;
    const std::filesystem::path path = std::filesystem::path(base) / ".." / "share" / "facetool" / "dlib" / file_name;
    std::error_code error;
    if (std::filesystem::is_regular_file(path, error)) return path.lexically_normal().string();
  }
  return "";
}

bool cpu_runs_avx2_engine() {
#if defined(FACETOOL_DETECTOR_AVX2_COPY)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

}  // namespace

std::string hog_detector_copy_path() { return build_copy_path("frontal_face_detector.dat"); }

std::string landmark_model_copy_path() { return build_copy_path("shape_predictor_68_face_landmarks.copy"); }

FaceDetector::FaceDetector(const std::string& landmark_model, const std::string& cnn_model, DetectorCode code) {
  const char* forced = std::getenv("FACETOOL_PORTABLE_DETECTOR");
  const bool portable_only = code == DetectorCode::portable || (forced && *forced && std::string(forced) != "0");
#if defined(FACETOOL_DETECTOR_AVX2_COPY)
  if (!portable_only && cpu_runs_avx2_engine()) {
    engine_ = avx2::make_face_detector_engine(landmark_model, cnn_model);
    code_name_ = "avx2";
    return;
  }
#endif
  (void)portable_only;
  engine_ = portable::make_face_detector_engine(landmark_model, cnn_model);
  code_name_ = "portable";
}

FaceDetector::~FaceDetector() = default;

bool FaceDetector::avx2_available() { return cpu_runs_avx2_engine(); }

void FaceDetector::prepare(DetectorChoice choice) { engine_->prepare(choice); }

namespace {

// Pixels of the photo padded for detection (DetectionOptions::padding of its shorter side on every side).
double padded_pixels(int width, int height, double padding) {
  const double pad = 2 * padding * std::min(width, height);
  return (width + pad) * (height + pad);
}

}  // namespace

double smallest_searchable_face(int width, int height, double padding) {
  constexpr double kWindow = 80, kMaxEnlargement = 4, kMaxSearchPixels = 32e6;
  const double padded = padded_pixels(width, height, padding);
  const double enlargement = std::min(kMaxEnlargement, std::sqrt(kMaxSearchPixels / std::max(padded, 1.0)));
  // Rounded up to a size band's start (window x 2^k, detection_bands.h), which is what is searched.
  return kWindow * std::exp2(std::ceil(std::log2(1.0 / enlargement) - 1e-9));
}

namespace {

// The automatic minimum face size of detect()'s first look.
double automatic_min_face(const RgbImage& photo) { return std::max(80.0, std::min(photo.width, photo.height) / 8.0); }

// Whether detect() looks again for small faces: the automatic minimum, a small photo, and a smaller size to look at.
bool looks_again_for_small_faces(const RgbImage& photo, const DetectionOptions& options) {
  return options.min_face_size == 0 && std::max(photo.width, photo.height) <= kSmallFaceFallbackSide &&
         std::max(kSmallFaceFallback, smallest_searchable_face(photo.width, photo.height, options.padding)) <
             automatic_min_face(photo);
}

// The smallest face detect() may search for: the minimum given (raised to what the search can
// afford), or the automatic one and its second look's.
double smallest_face_searched(const RgbImage& photo, const DetectionOptions& options) {
  const double smallest = smallest_searchable_face(photo.width, photo.height, options.padding);
  if (options.min_face_size > 0) return std::max(options.min_face_size, smallest);
  return looks_again_for_small_faces(photo, options) ? std::max(kSmallFaceFallback, smallest) : automatic_min_face(photo);
}

// Memory a detection needs beyond the photo: the padded, scaled grey photo and its HOG features
// (about 12 bytes a searched pixel) and, on the first detection of the process, OpenBLAS's
// buffers (two of 128 MB; dlib's landmark alignment calls into it, and OpenBLAS retries a failed
// allocation forever instead of failing, so the budget is checked before).
uint64_t detection_bytes(const RgbImage& photo, const DetectionOptions& options, bool first) {
  const double scale = std::max(1.0, 80.0 / smallest_face_searched(photo, options));
  return static_cast<uint64_t>(padded_pixels(photo.width, photo.height, options.padding) * scale * scale * 12) +
         (first ? (uint64_t{320} << 20) : 0);
}

}  // namespace

std::vector<DetectedFace> FaceDetector::detect(const RgbImage& photo, const DetectionOptions& options) {
  const std::string task = "detecting faces in a " + std::to_string(photo.width) + " x " + std::to_string(photo.height) + " photo";
  static std::atomic<bool> detected_before{false};
  const uint64_t bytes = detection_bytes(photo, options, !detected_before.load());
  check_memory_budget(bytes, task);
  std::vector<DetectedFace> faces = naming_out_of_memory(task, bytes, [&] { return detect_unchecked(photo, options); });
  detected_before = true;
  return faces;
}

std::vector<DetectedFace> FaceDetector::detect_unchecked(const RgbImage& photo, const DetectionOptions& options) {
  DetectionOptions searched = options;
  const double smallest = smallest_searchable_face(photo.width, photo.height, options.padding);
  if (options.min_face_size > 0 && options.min_face_size < smallest) {
    searched.min_face_size = smallest;
    static std::atomic<bool> said{false};
    if (!said.exchange(true))
      std::cerr << "note: facetool searches a " << photo.width << " x " << photo.height << " photo for faces of "
                << std::lround(smallest) << " pixels and more; --min-face-size " << options.min_face_size
                << " is raised to that (noted once)\n";
  }
  std::vector<DetectedFace> faces = engine_->detect(photo, searched);
  if (faces.empty() && looks_again_for_small_faces(photo, options)) {
    const double detection = engine_->detection_seconds, landmarks = engine_->landmark_seconds;
    searched.min_face_size = std::max(kSmallFaceFallback, smallest);
    faces = engine_->detect(photo, searched);
    engine_->detection_seconds += detection;
    engine_->landmark_seconds += landmarks;
  }
  return faces;
}

Landmarks68 FaceDetector::landmarks_in_box(const RgbImage& photo, double left, double top, double right,
                                           double bottom) {
  return engine_->landmarks_in_box(photo, left, top, right, bottom);
}

double FaceDetector::last_detection_seconds() const { return engine_->detection_seconds; }
double FaceDetector::last_landmark_seconds() const { return engine_->landmark_seconds; }

std::string no_face_reason(const RgbImage& photo, const DetectionOptions& options) {
  const double shorter = std::min(photo.width, photo.height);
  std::ostringstream why;
  if (options.min_face_size > shorter * (1 + 2 * options.padding)) {
    why << "no face: the photo (" << photo.width << " x " << photo.height
        << ") is smaller than the minimum face size " << options.min_face_size
        << " (--min-face-size; min_face_size in Python and in the C++ API's DetectionOptions)";
    return why.str();
  }
  const double min_size = smallest_face_searched(photo, options);
  why << "no face found by "
      << (options.detector == DetectorChoice::automatic ? "the HOG or the CNN detector"
          : options.detector == DetectorChoice::hog     ? "the HOG detector (try the CNN detector: --detector cnn)"
                                                        : "the CNN detector")
      << " among faces of at least " << std::lround(0.8 * min_size)
      << " pixels (try a smaller minimum face size: --min-face-size, or min_face_size in Python and in the "
         "C++ API's DetectionOptions)";
  return why.str();
}

}  // namespace facetool
