// FaceDetector: every face in a photo with its detection score and 68 landmarks (dlib's HOG
// frontal face detector, its MMOD CNN face detector and its 68-point shape predictor; dlib stays
// inside the .cpp files).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "libs/face/cnn_face_detector.h"
#include "libs/face/landmarks68.h"
#include "libs/io/image_io.h"

namespace facetool {

// Debian libdlib-data's model; its training data (iBUG 300-W) excludes commercial use.
extern const char* const kDefaultLandmarkModel;

// The build's decoded copy of dlib's HOG frontal face detector (<program or libfacetool_core
// folder>/../share/facetool/dlib/frontal_face_detector.dat, written by the build step
// libs/face/tools/write_hog_detector.cpp), or "" when there is none. FaceDetector reads it in a
// few milliseconds instead of decoding dlib's built-in copy (about 0.3 s at every start); a
// missing or unreadable copy falls back to dlib's.
std::string hog_detector_copy_path();
// The build's copy of dlib's 68-point landmark model as plain arrays (the same folder,
// shape_predictor_68_face_landmarks.copy, written by libs/face/tools/write_landmark_model.cpp),
// or "". FaceDetector reads it instead of dlib's file when it was made from that file as it is
// now (about 0.17 s instead of 0.65 s at every start; libs/face/landmark_model_copy.h).
std::string landmark_model_copy_path();

// Which detector finds the faces: dlib's HOG detector, its CNN (MMOD) detector, or `automatic`:
// HOG on the upright and turned photo, and the CNN on the upright photo as well when HOG finds
// no face of the default minimum size (docs/photos.md: the CNN is much slower than HOG on a CPU).
enum class DetectorChoice { hog, cnn, automatic };
const char* detector_choice_name(DetectorChoice choice);  // "hog", "cnn", "auto"
// Parses "hog", "cnn" or "auto"; throws facetool::Error naming the value otherwise.
DetectorChoice parse_detector_choice(const std::string& name);

struct DetectedFace {
  double left = 0, top = 0, right = 0, bottom = 0;  // detector box, photo pixels
  double score = 0;  // the detector's margin (> threshold: a face); HOG and CNN scales differ
  std::string detector = "hog";                      // which one found it: "hog" or "cnn"
  Landmarks68 landmarks{};                           // photo pixels
  double rotation_deg = 0;  // the photo turn it was found at (fallback_rotations_deg), or 0
  double padding = 0;       // pixels the photo was padded by on every side for the search (a face
                            // found again in a brightened crop keeps its first search's)
  // How far apart the fit and the mirrored fit of the kept landmarks were (mean distance of the
  // 51 inner points over the inter-ocular distance; docs/photos.md, "Landmark agreement"); -1
  // when not measured (mirror_landmarks off). Large values mark doubtful landmarks.
  double landmark_disagreement = -1;
  bool landmarks_retried = false;  // fitted again in other boxes because the first pair disagreed
  // Found (box and landmarks) in the photo brightened for hard light
  // (DetectionOptions::brightened_pass_disagreement).
  bool brightened = false;
  // The box the kept landmarks were fitted in: "hog" (HOG's, also for a CNN face that HOG boxed
  // on a second look, DetectionOptions::hog_box_for_cnn_faces) or "cnn" (the CNN's, mapped).
  std::string landmark_box = "hog";
  double size() const { return std::max(right - left, bottom - top); }
  // How it was found, for reports: the detector, "-turned" when found in a turned photo
  // ("hog", "hog-turned", "cnn", "cnn-turned").
  std::string found_by() const { return rotation_deg != 0 ? detector + "-turned" : detector; }
};

struct DetectionOptions {
  DetectorChoice detector = DetectorChoice::automatic;
  int max_faces = 0;            // keep the best-scoring this many (0: all)
  // Photo pixels; 0: automatic, max(80, shorter side / 8), and on a photo of up to 640 pixels a
  // side where that finds no face, 40 (small_face_fallback). The search runs in size bands that
  // start at 80 x 2^k, the largest such size not above the minimum (detection_bands.h), and
  // keeps faces of at least 0.8 times the minimum: a smaller minimum never finds fewer faces. A
  // minimum below smallest_searchable_face() is raised to it (said once on stderr).
  double min_face_size = 0;
  double score_threshold = 0.25;     // HOG margin below which a box is not a face
  double cnn_score_threshold = 0.0;  // CNN score below which a box is not a face
  // The photo is padded on every side by this fraction of its shorter side, with its mean
  // colour, before detection, so that a face filling the photo or cut by its edge is found.
  // (Bounding it by the default face size to save time on big photos broke the alignment of a
  // photo turned by 30 degrees: tests/face/photo_test.cpp.)
  double padding = 0.25;
  // The landmark model was trained on HOG boxes: CNN boxes are mapped to that convention first
  // (false: the CNN's own box, for measurements; docs/photos.md, "Landmark boxes").
  bool map_cnn_boxes = true;
  // A face only the CNN found is looked for again by HOG at the margin cnn_face_hog_margin (below
  // score_threshold), in a crop around it; when HOG boxes it there, its landmarks are fitted in
  // that box instead of the mapped CNN box (docs/photos.md, "Landmark boxes").
  bool hog_box_for_cnn_faces = true;
  double cnn_face_hog_margin = -1.0;
  // Fit the landmarks a second time in the HOG-convention box derived from the first fit.
  bool refit_landmarks = false;
  // Fit the landmarks also on the mirrored face and average the two fits (the mirrored fit's
  // points un-mirrored, left and right swapped): docs/photos.md, "Landmark boxes".
  bool mirror_landmarks = true;
  // With mirror_landmarks: when the fit and the mirrored fit disagree by more than this (the
  // mean distance of the 51 inner points over the inter-ocular distance), both are fitted again
  // in six boxes around the detector's (scaled by 0.9 and 1.1, moved by 6 % of its size each
  // way) and the most self-consistent pair is kept (docs/photos.md, "Landmark agreement"). 0:
  // always; negative: never. 0.05 retries about 1.5 % of the faces of UTKFace photos.
  double landmark_retry_disagreement = 0.05;
  // A face whose mirrored landmark fits disagree by more than this (after the retry above), and
  // whose box is partly in shadow (below), is looked for again in the photo brightened (each
  // sRGB byte v as 255 (v / 255)^0.5: the shadows of a hard-lit face lifted), in a crop around
  // it, and takes that look's box and landmarks when their mirrored fits agree better; a photo
  // without a face is searched again whole, brightened (docs/photos.md, "Hard light").
  // Negative: never; needs mirror_landmarks.
  double brightened_pass_disagreement = 0.02;
  // ... and at least this fraction of the middle of its box (central 60 % each way) in shadow
  // (sRGB luma below 0.25): brightening helps only where there are shadows to lift (an evenly
  // lit face keeps its first look).
  double brightened_pass_min_shadow = 0.2;
  // Fit the landmarks on a chip scaled so that the box is at least this many pixels wide and at
  // most twice this (0: at the photo's scale). dlib gives whole pixels, so small faces gain
  // sub-pixel points; big ones cost less.
  double landmark_box_pixels = 200;
  // When the upright photo has no face, the photo turned by these angles (degrees, counter-
  // clockwise on screen) is searched in turn until one has; the HOG detector finds only
  // roughly upright faces (about +-20 degrees of roll).
  std::vector<double> fallback_rotations_deg = {-30, 30, -90, 90, 180};
};

// Which compiled copy of the detector runs (the same code and results; docs/photos.md, "Speed"):
// the fastest this CPU can run (dlib's code built for AVX2 where the build and the CPU have it),
// or the portable one, which the tests compare it with. FACETOOL_PORTABLE_DETECTOR=1 in the
// environment makes `fastest` portable too.
enum class DetectorCode { fastest, portable };

class FaceDetectorEngine;

class FaceDetector {
 public:
  // Loads the landmark model (about one second); throws facetool::Error naming the file and
  // the Debian package when it is missing or unreadable. The CNN model is read when a detection
  // first needs it (or by prepare()).
  explicit FaceDetector(const std::string& landmark_model = kDefaultLandmarkModel,
                        const std::string& cnn_model = kDefaultCnnFaceModel,
                        DetectorCode code = DetectorCode::fastest);
  ~FaceDetector();
  FaceDetector(const FaceDetector&) = delete;
  FaceDetector& operator=(const FaceDetector&) = delete;

  // Reads the models that `choice` needs now (the CNN model for cnn and automatic), so that a
  // missing or damaged file stops a run before its first photo; throws facetool::Error naming it.
  void prepare(DetectorChoice choice);

  // Faces of `photo` (linear RGB; converted to sRGB for dlib), HOG faces first, each detector's
  // best score first. The detectors run on the padded photo scaled so that each size band's
  // face size becomes their 80-pixel window (faster on big photos); landmarks are fitted at
  // full resolution, in a box of the HOG detector's convention (CNN boxes are mapped to it).
  // Throws OutOfMemory ("out of memory while detecting faces in a W x H photo (needs ~N GB)")
  // before searching when the memory left (ulimit -v included) cannot hold the search.
  std::vector<DetectedFace> detect(const RgbImage& photo, const DetectionOptions& options = {});
  // Landmarks only, in a given box (HOG convention) (photo pixels): for tests on rendered faces with known boxes.
  Landmarks68 landmarks_in_box(const RgbImage& photo, double left, double top, double right,
                               double bottom);

  // Seconds the last detect() spent in detection and in the landmark fit (for benchmarks).
  double last_detection_seconds() const;
  double last_landmark_seconds() const;
  // The copy that runs: "avx2" or "portable".
  const char* code_name() const { return code_name_; }
  // Whether this build has the AVX2 copy and this CPU can run it.
  static bool avx2_available();

 private:
  std::vector<DetectedFace> detect_unchecked(const RgbImage& photo, const DetectionOptions& options);

  std::unique_ptr<FaceDetectorEngine> engine_;
  const char* code_name_ = "portable";
};

// The smallest face a search of a `width` x `height` photo looks for: the detector's 80-pixel
// window over the photo enlarged at most 4 times, and only while the padded, enlarged photo
// stays within 32 million pixels (a bigger photo is searched at scales below 1: its smallest
// face grows with it, so that no minimum makes a search run for minutes), rounded up to the
// start of a size band (80 x 2^k: 20, 40, 80, 160, ...).
double smallest_searchable_face(int width, int height, double padding);

// The automatic minimum's second look (DetectionOptions::min_face_size): faces down to this many
// pixels (kept from 0.8 times it) on photos of at most kSmallFaceFallbackSide pixels a side.
constexpr double kSmallFaceFallback = 40;
constexpr int kSmallFaceFallbackSide = 640;

// Why detect() found no face in `photo` (for the message and the summary): the photo is smaller
// than the minimum face size, or no detector found one, with what to try.
std::string no_face_reason(const RgbImage& photo, const DetectionOptions& options);

}  // namespace facetool
