// The face detector's work on dlib: HOG and CNN detection in size bands on a padded, scaled copy
// of the photo, shape prediction at full size. Compiled twice: here for any CPU, and by
// face_detector_engine_avx2.cpp for AVX2 (FaceDetector picks one at construction). In that copy
// dlib's namespace is renamed and only what lies between the two FACETOOL_DETECTOR_AVX2 blocks
// below (dlib's headers and this file's code) is compiled for AVX2; every other header must be
// included above them, so that the standard library's and facetool's inline code stays the same
// in both copies (the linker keeps one copy of it for the whole program).
#ifndef FACETOOL_DETECTOR_CODE
#define FACETOOL_DETECTOR_CODE portable
#endif

#include "libs/face/face_detector_engine.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>

#include "libs/face/detection_bands.h"
#include "libs/face/landmark_model_copy.h"
#include "core/util/error.h"
#include "core/util/memory_budget.h"
#include "core/util/parallel_for.h"
#include "core/util/math_constants.h"
#include "core/util/file_checks.h"
#include "core/util/stage_timer.h"

#if defined(FACETOOL_DETECTOR_AVX2)
#pragma GCC push_options
#pragma GCC target("avx2")
#endif

#include <dlib/image_processing.h>
#include <dlib/image_processing/frontal_face_detector.h>
#include <dlib/image_transforms.h>
#include <dlib/serialize.h>

#include "libs/face/hog_scan.h"
#include "libs/face/landmark_model_dlib.h"
#include "libs/face/landmark_trees.h"

namespace facetool {
namespace FACETOOL_DETECTOR_CODE {

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
      grey[y][x] = linear_to_srgb8(luma);  // the byte of lround(255 * linear_to_srgb(luma))
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

// dlib's frontal face detector: the build's decoded copy when found and readable (a few
// milliseconds), else dlib's built-in copy, decoded by the portable engine (about 0.3 s; dlib's
// decoder is compiled into libdlib for the portable copy only) and read back here.
dlib::frontal_face_detector load_hog_detector() {
  const std::string copy = hog_detector_copy_path();
  if (!copy.empty()) {
    try {
      dlib::frontal_face_detector detector;
      dlib::deserialize(copy) >> detector;
      if (detector.num_detectors() > 0) return detector;
    } catch (const std::exception&) {  // damaged: dlib's own copy is the same detector
    }
  }
  std::istringstream in(portable::builtin_hog_detector_bytes());
  dlib::frontal_face_detector detector;
  dlib::deserialize(detector, in);
  return detector;
}

#if !defined(FACETOOL_DETECTOR_RENAMED_DLIB)
std::string builtin_hog_detector_bytes() {
  std::ostringstream out;
  dlib::serialize(dlib::get_frontal_face_detector(), out);
  return out.str();
}
#endif

// dlib's HOG detector over all pyramid levels (the last size band; and the look again at a face
// only the CNN found), the same filters over one octave (the other bands), and a copy of that
// one per band, so that the bands are searched in parallel (a dlib detector keeps the image it
// scans: one object per thread). The bands search only windows centred on the photo (HogScan).
struct HogDetectors {
  dlib::frontal_face_detector all_levels = load_hog_detector();
  HogScan last_band{all_levels, HogScan::Windows::centred_on_the_varied_area};
  HogScan band{one_octave(all_levels), HogScan::Windows::centred_on_the_varied_area};
  std::vector<HogScan> band_copies;
};

class DlibEngine final : public FaceDetectorEngine {
 public:
  DlibEngine(const std::string& landmark_model, const std::string& cnn_model);
  void prepare(DetectorChoice choice) override;
  std::vector<DetectedFace> detect(const RgbImage& photo, const DetectionOptions& options) override;
  Landmarks68 landmarks_in_box(const RgbImage& photo, double left, double top, double right,
                               double bottom) override;

 private:
  // One detection over the photo, or over its brightened copy. `near_minimum`: search only the
  // size bands from the minimum face size up (no smaller default-size bands for the decision
  // to turn the photo or run the CNN), for a second look at a known face.
  std::vector<DetectedFace> detect_pass(const RgbImage& photo, const DetectionOptions& options, bool brighten,
                                        bool near_minimum = false);
  HogDetectors hog_;
  LandmarkTrees predictor_;
  std::string cnn_model_;
  std::unique_ptr<CnnFaceDetector> cnn_;  // read on first use
};

DlibEngine::DlibEngine(const std::string& landmark_model, const std::string& cnn_model) {
  std::error_code error;
  check(std::filesystem::exists(landmark_model, error) || error, "landmark model '", landmark_model,
        "' not found: install Debian's libdlib-data (scripts/install-dependencies.sh) or pass "
        "--landmark-model FILE");
  check_regular_input_file(landmark_model, kMaxWeightsFileBytes, "landmark model");  // no pipes
  StageTimer timer("load models");
  try {
    if (std::optional<MappedLandmarkModel> mapped = map_landmark_model_copy(landmark_model_copy_path(), landmark_model)) {
      predictor_ = LandmarkTrees(std::move(*mapped));
    } else {  // dlib's file itself (the same model, parsed in 0.65 s)
      std::ifstream in(landmark_model, std::ios::binary);
      check(static_cast<bool>(in), "cannot open it");
      predictor_ = LandmarkTrees(landmark_model_copy_of(in));
    }
  } catch (const std::bad_alloc&) {
    std::error_code size_error;
    const uintmax_t size = std::filesystem::file_size(landmark_model, size_error);
    throw out_of_memory("reading the landmark model '" + landmark_model + "'", size_error ? 0 : 2 * size);
  } catch (const std::exception& e) {
    fail("cannot read landmark model '", landmark_model, "': ", e.what(),
         " (expected dlib's shape_predictor_68_face_landmarks.dat)");
  }
  check(predictor_.num_parts() == kLandmarkCount, "landmark model '", landmark_model,
        "' predicts ", predictor_.num_parts(), " points; facetool needs the 68-point model");
  cnn_model_ = cnn_model;
}

void DlibEngine::prepare(DetectorChoice choice) {
  if (choice != DetectorChoice::hog && !cnn_)
    cnn_ = std::make_unique<CnnFaceDetector>(cnn_model_);
}

namespace {

constexpr double kWindow = 80;  // both detectors' window, pixels

// The shape predictor is most accurate on upright faces: when the eye line of a first fit is
// tilted by more than kRefitRollDeg, fit again on a chip of the photo turned upright around the
// face and map the points back.
constexpr double kRefitRollDeg = 8;

// The eye line's angle (radians, y down) from the centres of the two eyes' six points.
double eye_line_roll(const Landmarks68& landmarks) {
  Point2 left, right;
  for (int i = 36; i < 42; ++i) {
    left.x += landmarks[i].x / 6;
    left.y += landmarks[i].y / 6;
    right.x += landmarks[i + 6].x / 6;
    right.y += landmarks[i + 6].y / 6;
  }
  return std::atan2(right.y - left.y, right.x - left.x);
}

void refit_upright(const LandmarkTrees& predictor, const dlib::array2d<unsigned char>& grey,
                   const dlib::drectangle& box, Landmarks68& landmarks) {
  const double roll = eye_line_roll(landmarks);
  if (std::abs(roll) < kRefitRollDeg * kPi / 180) return;
  const dlib::dpoint centre = dlib::center(box);
  const double size = std::max(box.width(), box.height());
  const long chip = std::clamp(std::lround(2 * size), 64L, 800L);  // the box plus a margin
  const dlib::chip_details details(dlib::centered_drect(centre, 2 * size, 2 * size),
                                   dlib::chip_dims(chip, chip), roll);
  dlib::array2d<unsigned char> upright;
  dlib::extract_image_chip(grey, details, upright);
  const long quarter = chip / 4;
  const dlib::full_object_detection shape =
      predictor(upright, dlib::rectangle(quarter, quarter, chip - quarter, chip - quarter));
  const dlib::point_transform_affine back = dlib::inv(dlib::get_mapping_to_chip(details));
  for (int i = 0; i < kLandmarkCount; ++i) {
    const dlib::dpoint q = back(dlib::dpoint(shape.part(i).x(), shape.part(i).y()));
    landmarks[i] = {q.x(), q.y()};
  }
}

// The 68-point layout (Multi-PIE / iBUG) seen in a mirror: the index of each point's
// counterpart on the other side of the face (points on the midline keep theirs).
constexpr std::array<int, kLandmarkCount> kMirroredIndex = {
    16, 15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0,  // jaw
    26, 25, 24, 23, 22, 21, 20, 19, 18, 17,                    // brows
    27, 28, 29, 30,                                            // nose bridge
    35, 34, 33, 32, 31,                                        // nostrils
    45, 44, 43, 42, 47, 46, 39, 38, 37, 36, 41, 40,            // eyes
    54, 53, 52, 51, 50, 49, 48, 59, 58, 57, 56, 55,            // outer lips
    64, 63, 62, 61, 60, 67, 66, 65};                           // inner lips

// The photo around an inclusive box `box` as the predictor sees it: turned by `roll` (radians)
// about the box centre and scaled by `scale`, with a margin of a quarter of the box on every
// side. With roll 0 and scale 1 it is an exact copy of the pixels.
struct Chip {
  dlib::array2d<unsigned char> image;
  dlib::point_transform_affine to_chip;  // photo pixels to chip pixels
  double centre_x = 0, centre_y = 0, half_width = 0, half_height = 0;  // the box in the chip
};

Chip make_chip(const dlib::array2d<unsigned char>& grey, const dlib::rectangle& box, double roll, double scale) {
  const long side = std::max(box.right() - box.left(), box.bottom() - box.top());  // pixel centres
  const long margin = (side + 3) / 4;
  const double extent = static_cast<double>(side + 2 * margin);
  const long size = std::lround(extent * scale) + 1;
  const double left = static_cast<double>(box.left() - margin), top = static_cast<double>(box.top() - margin);
  const dlib::chip_details details(dlib::drectangle(left, top, left + extent, top + extent),
                                   dlib::chip_dims(size, size), roll);
  Chip chip;
  dlib::extract_image_chip(grey, details, chip.image);
  chip.to_chip = dlib::get_mapping_to_chip(details);
  const dlib::dpoint centre((box.left() + box.right()) / 2.0, (box.top() + box.bottom()) / 2.0);
  const double s = dlib::length(chip.to_chip(centre + dlib::dpoint(1, 0)) - chip.to_chip(centre));
  const dlib::dpoint c = chip.to_chip(centre);
  chip.centre_x = c.x();
  chip.centre_y = c.y();
  chip.half_width = s * (box.right() - box.left()) / 2;
  chip.half_height = s * (box.bottom() - box.top()) / 2;
  return chip;
}

// One fit of the predictor on `chip`, mirrored left to right if asked; the points come back in
// photo pixels, in the unmirrored layout.
Landmarks68 fit_on_chip(const LandmarkTrees& predictor, const Chip& chip, bool mirror) {
  const long width = chip.image.nc();
  const double cx = mirror ? width - 1 - chip.centre_x : chip.centre_x;
  const dlib::rectangle box(std::lround(cx - chip.half_width), std::lround(chip.centre_y - chip.half_height),
                            std::lround(cx + chip.half_width), std::lround(chip.centre_y + chip.half_height));
  dlib::full_object_detection shape;
  if (mirror) {
    dlib::array2d<unsigned char> flipped;
    dlib::flip_image_left_right(chip.image, flipped);
    shape = predictor(flipped, box);
  } else {
    shape = predictor(chip.image, box);
  }
  check(shape.num_parts() == kLandmarkCount, "the landmark model gives ", shape.num_parts(),
        " points; facetool needs a 68-point model");
  const dlib::point_transform_affine back = dlib::inv(chip.to_chip);
  Landmarks68 out;
  for (int i = 0; i < kLandmarkCount; ++i) {
    const double x = static_cast<double>(shape.part(i).x()), y = static_cast<double>(shape.part(i).y());
    const dlib::dpoint q = back(dlib::dpoint(mirror ? width - 1 - x : x, y));
    out[mirror ? kMirroredIndex[i] : i] = {q.x(), q.y()};
  }
  return out;
}

// The landmark model was trained on boxes of dlib's HOG detector. A CNN box (same face) is
// mapped to that convention: centre moved by (dx, dy) box sizes, side scaled by `scale`; the
// constants are the median relation of the two detectors' boxes on faces both found
// (docs/photos.md, "Landmark boxes").
struct BoxMapping {
  double dx = 0, dy = 0, scale = 1;
};
const BoxMapping kCnnToHog{0.057, 0.093, 0.941};

// The same relation between the bounding box of the 68 landmarks that the model gives in a HOG
// box and that box.
const BoxMapping kLandmarksToHog{0.0238, -0.0584, 0.994};

dlib::drectangle mapped_box(double left, double top, double right, double bottom, const BoxMapping& m) {
  const double size = std::max(right - left, bottom - top);
  const double cx = (left + right) / 2 + m.dx * size, cy = (top + bottom) / 2 + m.dy * size;
  const double half = m.scale * size / 2;
  return dlib::drectangle(cx - half, cy - half, cx + half, cy + half);
}

dlib::drectangle to_hog_convention(const ScoredBox& b, const std::string& detector, bool map_cnn) {
  if (detector != "cnn" || !map_cnn) return dlib::drectangle(b.left, b.top, b.right, b.bottom);
  return mapped_box(b.left, b.top, b.right, b.bottom, kCnnToHog);
}

dlib::drectangle box_from_landmarks(const Landmarks68& l) {
  double lx = 1e300, ly = 1e300, hx = -1e300, hy = -1e300;
  for (const Point2& p : l) {
    lx = std::min(lx, p.x);
    ly = std::min(ly, p.y);
    hx = std::max(hx, p.x);
    hy = std::max(hy, p.y);
  }
  return mapped_box(lx, ly, hx, hy, kLandmarksToHog);
}

// A HOG box more than this factor larger or smaller than the CNN box mapped to HOG's convention,
// or whose centre is further than kHogBoxMaxShift of that box's side from its centre, is another
// reading of the face (on hard-lit photos the lit half with the background beside it, on rolled
// faces the top of the head), not its box; one step of HOG's pyramid is 1.2 (docs/photos.md,
// "Landmark boxes").
constexpr double kHogBoxMaxSizeRatio = 1.25;
constexpr double kHogBoxMaxShift = 0.25;

// The box HOG gives a face the CNN found (`cnn_box`, work-image pixels; `mapped` the same box in
// HOG's convention), looking again at `margin` (below its threshold: at yaw HOG scores the face
// low but still boxes it the way the landmark model was trained with) in a crop around it,
// scaled so that the face is about 100 pixels wide: the best-scoring box on the same face, of
// about the mapped box's size and place, or none.
std::optional<dlib::drectangle> hog_box_near(dlib::frontal_face_detector& hog, const dlib::array2d<unsigned char>& grey,
                                             const ScoredBox& cnn_box, const dlib::drectangle& mapped, double margin) {
  const double size = cnn_box.size(), grow = 0.5 * size, scale = 100.0 / size;
  const long x0 = std::max(0L, std::lround(cnn_box.left - grow)), y0 = std::max(0L, std::lround(cnn_box.top - grow));
  const long x1 = std::min(grey.nc(), std::lround(cnn_box.right + grow));
  const long y1 = std::min(grey.nr(), std::lround(cnn_box.bottom + grow));
  if (x1 <= x0 || y1 <= y0) return std::nullopt;
  dlib::array2d<unsigned char> scaled(std::max(1L, std::lround((y1 - y0) * scale)),
                                      std::max(1L, std::lround((x1 - x0) * scale)));
  dlib::resize_image(dlib::sub_image(grey, dlib::rectangle(x0, y0, x1 - 1, y1 - 1)), scaled,
                     dlib::interpolate_bilinear());
  std::vector<dlib::rect_detection> found;
  hog(scaled, found, margin);
  const double side = std::max(mapped.width(), mapped.height());
  const dlib::dpoint centre = dlib::center(mapped);
  std::optional<dlib::drectangle> best;
  double best_score = -1e300;
  for (const dlib::rect_detection& d : found) {
    const ScoredBox b{d.rect.left() / scale + x0, d.rect.top() / scale + y0, (d.rect.right() + 1) / scale + x0,
                      (d.rect.bottom() + 1) / scale + y0, d.detection_confidence};
    const double ratio = b.size() / side;
    const double shift = std::hypot(0.5 * (b.left + b.right) - centre.x(), 0.5 * (b.top + b.bottom) - centre.y()) / side;
    if (same_face(b, cnn_box) && ratio <= kHogBoxMaxSizeRatio && ratio >= 1 / kHogBoxMaxSizeRatio &&
        shift <= kHogBoxMaxShift && b.score > best_score) {
      best_score = b.score;
      best = dlib::drectangle(b.left, b.top, b.right, b.bottom);
    }
  }
  return best;
}

Landmarks68 mean_of(const Landmarks68& a, const Landmarks68& b) {
  Landmarks68 mean;
  for (int i = 0; i < kLandmarkCount; ++i) mean[i] = {(a[i].x + b[i].x) / 2, (a[i].y + b[i].y) / 2};
  return mean;
}

// The fit on a chip and the fit on its mirror image, averaged, and how far apart they are: the
// mean distance of the 51 inner points (brows, nose, eyes, mouth) over the inter-ocular distance.
struct MirroredPair {
  Landmarks68 mean{};
  double disagreement = 0;
};

// `a` fitted on a chip, `b` on its mirror image (unmirrored layout), as a pair.
MirroredPair mirrored_pair(const Landmarks68& a, const Landmarks68& b) {
  const Point2 left_eye = {(a[36].x + a[39].x) / 2, (a[36].y + a[39].y) / 2};
  const Point2 right_eye = {(a[42].x + a[45].x) / 2, (a[42].y + a[45].y) / 2};
  const double iod = std::max(std::hypot(left_eye.x - right_eye.x, left_eye.y - right_eye.y), 1e-9);
  double sum = 0;
  for (int i = 17; i < kLandmarkCount; ++i) sum += std::hypot(a[i].x - b[i].x, a[i].y - b[i].y);
  return {mean_of(a, b), sum / (kLandmarkCount - 17) / iod};
}

MirroredPair fit_mirrored_pair(const LandmarkTrees& predictor, const Chip& chip) {
  return mirrored_pair(fit_on_chip(predictor, chip, false), fit_on_chip(predictor, chip, true));
}

// Boxes tried when the mirrored pair disagrees (DetectionOptions::landmark_retry_disagreement):
// the centre moved by (dx, dy) box sizes, the side scaled by `scale`. Six measured as well as
// twelve (docs/photos.md, "Landmark agreement").
constexpr BoxMapping kRetryBoxes[] = {{0, 0, 0.9}, {0, 0, 1.1},  {-0.06, 0, 1},
                                      {0.06, 0, 1}, {0, -0.06, 1}, {0, 0.06, 1}};

// The landmarks in `box` (HOG convention, work-image pixels): one fit in the box as it is
// (mirror_landmarks off, landmark_box_pixels 0), or on a chip scaled to landmark_box_pixels,
// averaged with the fit of the mirrored chip; a face whose eye line is tilted by more than
// kRefitRollDeg is fitted on a chip turned upright. When the fit and the mirrored fit disagree,
// the pair is fitted again in the boxes of kRetryBoxes and the most self-consistent pair kept.
// `face` gets the kept pair's disagreement and whether it was retried.
Landmarks68 fit_landmarks(const LandmarkTrees& predictor, const dlib::array2d<unsigned char>& grey,
                          const dlib::drectangle& box, const DetectionOptions& options, DetectedFace& face) {
  const dlib::rectangle whole(std::lround(box.left()), std::lround(box.top()), std::lround(box.right()) - 1,
                              std::lround(box.bottom()) - 1);
  if (!options.mirror_landmarks && options.landmark_box_pixels <= 0) {
    Landmarks68 landmarks = to_landmarks(predictor(grey, whole));
    refit_upright(predictor, grey, box, landmarks);
    return landmarks;
  }
  const double side = std::max(1L, std::max(whole.right() - whole.left(), whole.bottom() - whole.top()));
  // Small boxes are scaled up to landmark_box_pixels; boxes over twice that are scaled down to
  // twice that (the chip's cost grows with the box's area; the predictor needs no more).
  const double target = options.landmark_box_pixels > 0 ? options.landmark_box_pixels : side;
  const double scale = side < target ? target / side : side > 2 * target ? 2 * target / side : 1.0;
  const Chip upright_chip = make_chip(grey, whole, 0, scale);
  const Landmarks68 first = fit_on_chip(predictor, upright_chip, false);
  double roll = eye_line_roll(first);
  if (std::abs(roll) < kRefitRollDeg * kPi / 180) roll = 0;
  if (!options.mirror_landmarks)
    return roll == 0 ? first : fit_on_chip(predictor, make_chip(grey, whole, roll, scale), false);
  // Upright, the first fit is the pair's unmirrored half: only its mirror is fitted.
  MirroredPair best = roll == 0 ? mirrored_pair(first, fit_on_chip(predictor, upright_chip, true))
                                : fit_mirrored_pair(predictor, make_chip(grey, whole, roll, scale));
  face.landmark_disagreement = best.disagreement;
  if (options.landmark_retry_disagreement < 0 || best.disagreement <= options.landmark_retry_disagreement)
    return best.mean;
  face.landmarks_retried = true;
  for (const BoxMapping& m : kRetryBoxes) {
    const dlib::drectangle b = mapped_box(whole.left(), whole.top(), whole.right(), whole.bottom(), m);
    const dlib::rectangle moved(std::lround(b.left()), std::lround(b.top()), std::lround(b.right()),
                                std::lround(b.bottom()));
    const MirroredPair pair = fit_mirrored_pair(predictor, make_chip(grey, moved, roll, scale));
    if (pair.disagreement < best.disagreement) best = pair;
  }
  face.landmark_disagreement = best.disagreement;
  return best.mean;
}

// The photo as dlib sees it, padded on every side by `pad` pixels of its mean colour.
struct WorkImage {
  dlib::array2d<unsigned char> grey;   // sRGB-encoded luma: HOG and the landmark model
  dlib::array2d<dlib::rgb_pixel> rgb;  // sRGB: the CNN (only when it runs)
  bool brightened = false;             // both copies' bytes through brightening()
};

// The fraction of the middle of the face's box (its central 60 % each way, inside the photo:
// the face, not the hair or background in the box's corners) whose luma is in shadow: below 0.25
// in sRGB terms (linear 0.0508).
double shadow_fraction(const RgbImage& photo, const DetectedFace& face) {
  const double cx = (face.left + face.right) / 2, cy = (face.top + face.bottom) / 2;
  const double hw = 0.3 * (face.right - face.left), hh = 0.3 * (face.bottom - face.top);
  const int x0 = std::clamp(static_cast<int>(std::lround(cx - hw)), 0, photo.width);
  const int x1 = std::clamp(static_cast<int>(std::lround(cx + hw)), x0, photo.width);
  const int y0 = std::clamp(static_cast<int>(std::lround(cy - hh)), 0, photo.height);
  const int y1 = std::clamp(static_cast<int>(std::lround(cy + hh)), y0, photo.height);
  constexpr float kShadow = 0.0508f;  // srgb_to_linear(0.25)
  int64_t dark = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const float* p = photo.at(x, y);
      dark += 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2] < kShadow;
    }
  const int64_t all = static_cast<int64_t>(x1 - x0) * (y1 - y0);
  return all > 0 ? static_cast<double>(dark) / all : 0.0;
}

// The brightening of a hard-lit photo's sRGB bytes: v -> 255 (v / 255)^0.5.
const std::array<unsigned char, 256>& brightening() {
  static const std::array<unsigned char, 256> table = [] {
    std::array<unsigned char, 256> t{};
    for (int v = 0; v < 256; ++v) t[v] = static_cast<unsigned char>(std::lround(255 * std::sqrt(v / 255.0)));
    return t;
  }();
  return table;
}

WorkImage padded_work_image(const RgbImage& photo, long pad, bool brighten) {
  dlib::array2d<unsigned char> grey;
  to_grey(photo, grey);
  if (brighten)
    for (unsigned char& v : grey) v = brightening()[v];
  WorkImage work;
  work.brightened = brighten;
  const long w = photo.width, h = photo.height;
  const double mean_grey = std::accumulate(grey.begin(), grey.end(), 0.0) / (w * h);
  work.grey.set_size(h + 2 * pad, w + 2 * pad);
  dlib::assign_all_pixels(work.grey, static_cast<unsigned char>(std::lround(mean_grey)));
  for (long y = 0; y < h; ++y)
    for (long x = 0; x < w; ++x) work.grey[y + pad][x + pad] = grey[y][x];
  return work;
}

// The colour copy the CNN needs, made only when it runs (the sRGB encoding of a big photo costs
// more than HOG on it).
void add_colour(WorkImage& work, const RgbImage& photo, long pad) {
  if (work.rgb.size() > 0) return;
  const long w = photo.width, h = photo.height;
  double mean[3] = {0, 0, 0};
  std::vector<unsigned char> srgb(static_cast<size_t>(w) * h * 3);
  for (size_t i = 0; i < srgb.size(); ++i) {
    const unsigned char v = linear_to_srgb8(photo.pixels[i]);
    srgb[i] = work.brightened ? brightening()[v] : v;
    mean[i % 3] += srgb[i];
  }
  const dlib::rgb_pixel fill(static_cast<unsigned char>(std::lround(mean[0] / (w * h))),
                             static_cast<unsigned char>(std::lround(mean[1] / (w * h))),
                             static_cast<unsigned char>(std::lround(mean[2] / (w * h))));
  work.rgb.set_size(h + 2 * pad, w + 2 * pad);
  dlib::assign_all_pixels(work.rgb, fill);
  for (long y = 0; y < h; ++y)
    for (long x = 0; x < w; ++x) {
      const unsigned char* p = &srgb[(static_cast<size_t>(y) * w + x) * 3];
      work.rgb[y + pad][x + pad] = dlib::rgb_pixel(p[0], p[1], p[2]);
    }
}

struct Found {
  ScoredBox box;  // work-image pixels
  std::string detector;
};

// Every face of the upright work image, for faces of `min_size` pixels and more; `found_default`
// says whether a face of the default minimum size `default_size` or more was found (a decision
// that must not depend on min_size, or a smaller minimum could take the CNN's faces away).
std::vector<Found> search_upright(HogDetectors& hog_detectors, const CnnFaceDetector* cnn_detector,
                                  bool use_cnn, const WorkImage& work,
                                  const DetectionOptions& options, double min_size,
                                  double default_size, bool& found_default,
                                  double& detection_seconds) {
  const auto start = Clock::now();
  const double shorter = std::min(work.grey.nr(), work.grey.nc());
  const std::vector<SizeBand> wanted = size_bands(min_size, shorter, kWindow);
  const std::vector<SizeBand> all = size_bands(std::min(min_size, default_size), shorter, kWindow);
  const double default_band = size_bands(default_size, shorter, kWindow).empty()
                                  ? 1e300
                                  : size_bands(default_size, shorter, kWindow).back().face_size;
  auto scaled_boxes = [](std::vector<ScoredBox> boxes, double scale, const SizeBand& band) {
    std::vector<ScoredBox> kept;
    for (ScoredBox& b : boxes) {
      b.left /= scale;
      b.top /= scale;
      b.right /= scale;
      b.bottom /= scale;
      if (band.holds(b)) kept.push_back(b);
    }
    std::sort(kept.begin(), kept.end(), [](const ScoredBox& a, const ScoredBox& b) { return a.score > b.score; });
    return kept;
  };

  std::vector<std::vector<ScoredBox>> hog(all.size()), cnn(all.size());
  found_default = false;
  const bool run_hog = !use_cnn;
  while (run_hog && hog_detectors.band_copies.size() < all.size())
    hog_detectors.band_copies.push_back(hog_detectors.band);
  // The bands in parallel, the largest (most work) first; each writes its own hog[i].
  parallel_for(run_hog ? static_cast<int64_t>(all.size()) : 0, 1, [&](int64_t first, int64_t end) {
  for (size_t i = static_cast<size_t>(first); i < static_cast<size_t>(end); ++i) {
    const double scale = all[i].scale(kWindow);
    dlib::array2d<unsigned char> scaled;
    const dlib::array2d<unsigned char>* image = &work.grey;
    if (std::abs(scale - 1) > 1e-9) {
      scaled.set_size(std::max(1L, std::lround(work.grey.nr() * scale)), std::max(1L, std::lround(work.grey.nc() * scale)));
      dlib::resize_image(work.grey, scaled, dlib::interpolate_bilinear());
      image = &scaled;
    }
    std::vector<dlib::rect_detection> found;
    (all[i].last ? hog_detectors.last_band : hog_detectors.band_copies[i])(*image, found, options.score_threshold);
    std::vector<ScoredBox> boxes;
    for (const dlib::rect_detection& d : found)
      boxes.push_back({static_cast<double>(d.rect.left()), static_cast<double>(d.rect.top()),
                       static_cast<double>(d.rect.right() + 1), static_cast<double>(d.rect.bottom() + 1),
                       d.detection_confidence});
    hog[i] = scaled_boxes(boxes, scale, all[i]);
  }
  });
  for (size_t i = 0; run_hog && i < all.size(); ++i)
    if (all[i].face_size >= default_band && !hog[i].empty()) found_default = true;
  const bool run_cnn = use_cnn;
  for (size_t i = 0; run_cnn && i < all.size(); ++i) {
    const double scale = all[i].scale(kWindow);
    Srgb8Image input;
    input.height = static_cast<int>(std::max(1L, std::lround(work.rgb.nr() * scale)));
    input.width = static_cast<int>(std::max(1L, std::lround(work.rgb.nc() * scale)));
    dlib::array2d<dlib::rgb_pixel> scaled(input.height, input.width);
    if (std::abs(scale - 1) > 1e-9)
      dlib::resize_image(work.rgb, scaled, dlib::interpolate_bilinear());
    else
      dlib::assign_image(scaled, work.rgb);
    input.rgb.resize(static_cast<size_t>(input.width) * input.height * 3);
    for (long y = 0; y < input.height; ++y)
      for (long x = 0; x < input.width; ++x) {
        unsigned char* p = &input.rgb[(static_cast<size_t>(y) * input.width + x) * 3];
        p[0] = scaled[y][x].red;
        p[1] = scaled[y][x].green;
        p[2] = scaled[y][x].blue;
      }
    cnn[i] = scaled_boxes(cnn_detector->detect(input, options.cnn_score_threshold), scale, all[i]);
    if (all[i].face_size >= default_band && !cnn[i].empty()) found_default = true;
  }
  detection_seconds += seconds_since(start);

  // The wanted bands are the first wanted.size() of `all` (same grid, largest first).
  std::vector<std::vector<ScoredBox>> groups;
  std::vector<std::string> names;
  for (size_t i = 0; i < wanted.size(); ++i) {
    groups.push_back(hog[i]);
    names.push_back("hog");
    groups.push_back(cnn[i]);
    names.push_back("cnn");
  }
  const std::vector<std::vector<bool>> kept = merge_in_order(groups);
  std::vector<Found> faces;
  for (const char* detector : {"hog", "cnn"})
    for (size_t g = 0; g < groups.size(); ++g)
      if (names[g] == detector)
        for (size_t k = 0; k < groups[g].size(); ++k)
          if (kept[g][k] && groups[g][k].size() >= 0.8 * min_size) faces.push_back({groups[g][k], names[g]});
  std::stable_sort(faces.begin(), faces.end(), [](const Found& a, const Found& b) {
    return a.detector != b.detector ? a.detector == "hog" : a.box.score > b.box.score;
  });
  return faces;
}

}  // namespace

std::vector<DetectedFace> DlibEngine::detect(const RgbImage& photo,
                                               const DetectionOptions& options) {
  check(photo.width > 0 && photo.height > 0, "face detection: the photo is empty");
  check(options.padding >= 0 && options.padding <= 2, "face detection: padding ", options.padding,
        " is outside [0, 2]");
  prepare(options.detector);
  std::vector<DetectedFace> faces = detect_pass(photo, options, false);
  const double limit = options.brightened_pass_disagreement;
  if (limit < 0 || !options.mirror_landmarks) return faces;
  double detection = detection_seconds, landmarks = landmark_seconds;
  auto add_times = [&] {
    detection += detection_seconds;
    landmarks += landmark_seconds;
  };
  if (faces.empty()) {
    faces = detect_pass(photo, options, true);
    add_times();
    for (DetectedFace& f : faces) f.brightened = true;
  }
  auto box = [](const DetectedFace& f) { return ScoredBox{f.left, f.top, f.right, f.bottom, f.score}; };
  for (DetectedFace& f : faces) {
    if (f.brightened || f.landmark_disagreement <= limit ||
        shadow_fraction(photo, f) < options.brightened_pass_min_shadow)
      continue;
    // Looked for again in the brightened photo: in a crop around the face (its box grown by half
    // its size on every side), upright, in the size bands of faces from 0.8 times its size up,
    // by HOG alone when HOG found it.
    const double size = f.size(), grow = 0.5 * size;
    const int x0 = std::clamp(static_cast<int>(std::floor(f.left - grow)), 0, photo.width - 1);
    const int y0 = std::clamp(static_cast<int>(std::floor(f.top - grow)), 0, photo.height - 1);
    const int x1 = std::clamp(static_cast<int>(std::ceil(f.right + grow)), x0 + 1, photo.width);
    const int y1 = std::clamp(static_cast<int>(std::ceil(f.bottom + grow)), y0 + 1, photo.height);
    RgbImage crop;
    crop.width = x1 - x0;
    crop.height = y1 - y0;
    crop.pixels.resize(static_cast<size_t>(crop.width) * crop.height * 3);
    for (int y = y0; y < y1; ++y)
      std::copy(photo.at(x0, y), photo.at(x0, y) + 3 * crop.width, crop.at(0, y - y0));
    DetectionOptions again = options;
    again.fallback_rotations_deg.clear();
    again.min_face_size = 0.8 * size;
    again.max_faces = 0;
    if (options.detector == DetectorChoice::automatic && f.detector == "hog") again.detector = DetectorChoice::hog;
    std::vector<DetectedFace> lifted = detect_pass(crop, again, true, true);
    add_times();
    const DetectedFace original = f;
    for (DetectedFace& g : lifted) {
      g.left += x0, g.right += x0, g.top += y0, g.bottom += y0;
      for (Point2& p : g.landmarks) p.x += x0, p.y += y0;
      g.brightened = true;
      g.padding = original.padding;  // the photo's search padding, not the crop's
      if (same_face(box(original), box(g)) && g.landmark_disagreement >= 0 &&
          g.landmark_disagreement < f.landmark_disagreement)
        f = g;
    }
  }
  detection_seconds = detection;
  landmark_seconds = landmarks;
  return faces;
}

std::vector<DetectedFace> DlibEngine::detect_pass(const RgbImage& photo, const DetectionOptions& options,
                                                    bool brighten, bool near_minimum) {
  const auto whole_start = Clock::now();
  detection_seconds = landmark_seconds = 0;
  const auto start = Clock::now();
  const double shorter = std::min(photo.width, photo.height);
  const double automatic_size = std::max(80.0, shorter / 8.0);
  const double min_size = options.min_face_size > 0 ? options.min_face_size : automatic_size;
  const double default_size = near_minimum ? min_size : automatic_size;
  const long pad = std::lround(options.padding * shorter);
  WorkImage work = padded_work_image(photo, pad, brighten);
  detection_seconds += seconds_since(start);

  // Upright first; while no face of the default size is found, the photo turned by each
  // fallback angle in turn, its new faces mapped back and added.
  std::vector<DetectedFace> faces;
  std::vector<ScoredBox> work_boxes;  // the faces' boxes in the work image's frame
  auto add = [&](const std::vector<Found>& found, const dlib::array2d<unsigned char>& grey,
                 const dlib::point_transform_affine& back, double degrees) {
    const auto landmark_start = Clock::now();
    double second_look_seconds = 0;
    for (const Found& f : found) {
      if (options.max_faces > 0 && static_cast<int>(faces.size()) >= options.max_faces) break;
      double lx = 1e300, ly = 1e300, hx = -1e300, hy = -1e300;
      for (double x : {f.box.left, f.box.right})
        for (double y : {f.box.top, f.box.bottom}) {
          const dlib::dpoint q = back(dlib::dpoint(x, y));
          lx = std::min(lx, q.x());
          ly = std::min(ly, q.y());
          hx = std::max(hx, q.x());
          hy = std::max(hy, q.y());
        }
      const ScoredBox mapped{lx, ly, hx, hy, f.box.score};
      if (std::any_of(work_boxes.begin(), work_boxes.end(),
                      [&](const ScoredBox& b) { return same_face(b, mapped); }))
        continue;
      DetectedFace face;
      dlib::drectangle landmark_box = to_hog_convention(f.box, f.detector, options.map_cnn_boxes);
      face.landmark_box = f.detector;
      // A face only the CNN found is fitted in HOG's box for it when HOG boxes it at a lower
      // margin: the landmark model's own box convention (the mapped CNN box puts the points of
      // turned faces far off: docs/photos.md, "Landmark boxes"). HOG's second look counts as
      // detection time.
      if (f.detector == "cnn" && options.hog_box_for_cnn_faces) {
        const auto look_start = Clock::now();
        if (const std::optional<dlib::drectangle> hog_box = hog_box_near(
                hog_.all_levels, grey, f.box, to_hog_convention(f.box, f.detector, true), options.cnn_face_hog_margin)) {
          landmark_box = *hog_box;
          face.landmark_box = "hog";
        }
        second_look_seconds += seconds_since(look_start);
      }
      Landmarks68 landmarks = fit_landmarks(predictor_, grey, landmark_box, options, face);
      if (options.refit_landmarks)
        landmarks = fit_landmarks(predictor_, grey, box_from_landmarks(landmarks), options, face);
      for (int i = 0; i < kLandmarkCount; ++i) {
        const dlib::dpoint q = back(dlib::dpoint(landmarks[i].x, landmarks[i].y));
        face.landmarks[i] = {q.x() - pad, q.y() - pad};
      }
      face.left = lx - pad;
      face.top = ly - pad;
      face.right = hx - pad;
      face.bottom = hy - pad;
      face.score = f.box.score;
      face.detector = f.detector;
      face.rotation_deg = degrees;
      face.padding = static_cast<double>(pad);
      faces.push_back(face);
      work_boxes.push_back(mapped);
    }
    landmark_seconds += seconds_since(landmark_start) - second_look_seconds;
    detection_seconds += second_look_seconds;
  };

  // One detector over the upright photo and, while no face of the default size is found, over
  // the photo turned by each fallback angle.
  bool found_default = false;
  auto run = [&](bool use_cnn, bool turns) {
    found_default = false;
    if (use_cnn) {
      const auto colour_start = Clock::now();
      add_colour(work, photo, pad);
      detection_seconds += seconds_since(colour_start);
    }
    add(search_upright(hog_, cnn_.get(), use_cnn, work, options,
                       min_size, default_size, found_default, detection_seconds),
        work.grey, dlib::point_transform_affine(), 0.0);
    for (double degrees : options.fallback_rotations_deg) {
      if (found_default || !turns) break;
      const auto turn_start = Clock::now();
      WorkImage turned;
      turned.brightened = work.brightened;
      const double radians = degrees * kPi / 180.0;
      const dlib::point_transform_affine to_turned =
          dlib::rotate_image(work.grey, turned.grey, radians, dlib::interpolate_bilinear());
      if (use_cnn) dlib::rotate_image(work.rgb, turned.rgb, radians, dlib::interpolate_bilinear());
      detection_seconds += seconds_since(turn_start);
      add(search_upright(hog_, cnn_.get(), use_cnn, turned, options,
                         min_size, default_size, found_default, detection_seconds),
          turned.grey, dlib::inv(to_turned), degrees);
    }
  };
  // automatic: HOG (upright and turned) first; the CNN on the upright photo only when HOG found
  // no face of the default size in any turn (the CNN also answers some faces lying on their side
  // with boxes the landmark model cannot use, so HOG's turns go first).
  if (options.detector != DetectorChoice::cnn) run(false, true);
  if (options.detector == DetectorChoice::cnn) run(true, true);
  if (options.detector == DetectorChoice::automatic && !found_default) run(true, false);
  if (stage_timing_enabled()) {  // grey conversion and turning count as detection
    add_stage_time("landmarks", landmark_seconds);
    add_stage_time("detect", seconds_since(whole_start) - landmark_seconds);
  }
  return faces;
}

Landmarks68 DlibEngine::landmarks_in_box(const RgbImage& photo, double left, double top,
                                           double right, double bottom) {
  dlib::array2d<unsigned char> grey;
  to_grey(photo, grey);
  return to_landmarks(predictor_(
      grey, dlib::rectangle(std::lround(left), std::lround(top), std::lround(right),
                            std::lround(bottom))));
}

std::unique_ptr<FaceDetectorEngine> make_face_detector_engine(const std::string& landmark_model,
                                                              const std::string& cnn_model) {
  return std::make_unique<DlibEngine>(landmark_model, cnn_model);
}

}  // namespace FACETOOL_DETECTOR_CODE
}  // namespace facetool

#if defined(FACETOOL_DETECTOR_AVX2)
#pragma GCC pop_options
#endif
