// Photo-pipeline benchmarks on one photo and its 12-megapixel enlargement.
#include "apps/facetool/bench/photo_benchmarks.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "libs/face/face_crops.h"
#include "libs/face/frame_rotation.h"
#include "libs/face/landmark_drawing.h"
#include "libs/face/paste_back.h"
#include "libs/face/photo_reader.h"
#include "core/util/error.h"

namespace facetool {
namespace {

using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void bench_one(FaceDetector& detector, const RgbImage& photo, int size, int repeats, std::ostream& out,
               const DetectionOptions& options = {}, const char* note = "") {
  std::vector<double> detect, landmarks, align, paste;
  for (int r = 0; r < repeats; ++r) {
    const std::vector<DetectedFace> faces = detector.detect(photo, options);
    check(faces.size() == 1, "bench photo: expected one face, found ", faces.size());
    detect.push_back(detector.last_detection_seconds());
    landmarks.push_back(detector.last_landmark_seconds());
    auto t0 = Clock::now();
    const FaceCrop crop = crop_face(photo, faces[0], size, false);
    align.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    // Paste-back of every output: alpha, albedo, normal (rotated), visibility (rotated), shading,
    // reconstruction, as infer does.
    const size_t crop_plane = static_cast<size_t>(size) * size, plane = static_cast<size_t>(photo.width) * photo.height;
    std::vector<float> crop_data(crop_plane * 21, 0.5f), layers(plane * 22, 0.0f);
    t0 = Clock::now();
    const Similarity2& t = crop.alignment.photo_to_crop;
    rotate_normals_to_photo(crop_data.data() + 3 * crop_plane, crop_plane, t);
    rotate_visibility_to_photo(crop_data.data() + 6 * crop_plane, crop_plane, t);
    const PasteRegion region = paste_region(photo.width, photo.height, t, size, crop.mask_polygon, 3.0);
    paste_channels(region, crop_data.data(), 21, layers.data() + plane, photo.width, photo.height);
    paste_channels(region, crop_data.data(), 1, layers.data(), photo.width, photo.height);
    paste.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  char line[240];
  const double total = median(detect) + median(landmarks) + median(align) + median(paste);
  std::snprintf(line, sizeof line, "%-4s %5d x %-5d %6.1f MP | detect %8.1f ms | landmarks %6.1f ms | align %6.1f ms | paste-back %6.1f ms | total %8.1f ms%s\n",
                detector_choice_name(options.detector), photo.width, photo.height, photo.width * photo.height / 1e6, median(detect) * 1e3,
                median(landmarks) * 1e3, median(align) * 1e3, median(paste) * 1e3, total * 1e3, note);
  out << line;
}

}  // namespace

void run_photo_benchmarks(const std::string& photo_path, int crop_size, int repeats, std::ostream& out) {
  FaceDetector detector;
  const RgbImage photo = read_photo(photo_path);
  out << "photo pipeline on cpu (" << photo_path << ", crop " << crop_size << ", median of "
      << repeats << "; the 12 MP photo is the same one enlarged; detector auto, then hog and cnn alone; "
      << detector.code_name() << " copy of the detector)\n";
  // The default landmark fit (mirrored, on a chip) and one plain fit in the box.
  DetectionOptions one_fit;
  one_fit.mirror_landmarks = false;
  one_fit.landmark_box_pixels = 0;
  const char* one_fit_note = " (one landmark fit, not mirrored)";
  bench_one(detector, photo, crop_size, repeats, out);
  bench_one(detector, photo, crop_size, repeats, out, one_fit, one_fit_note);
  // The cost for a face whose fit and mirrored fit disagree: the pair again in six more boxes.
  DetectionOptions retried;
  retried.landmark_retry_disagreement = 0;
  bench_one(detector, photo, crop_size, repeats, out, retried, " (landmarks retried in six more boxes)");
  const int width = static_cast<int>(std::lround(std::sqrt(12e6 * photo.width / photo.height)));
  const RgbImage large = resize_to_width(photo, width);
  bench_one(detector, large, crop_size, repeats, out);
  bench_one(detector, large, crop_size, repeats, out, one_fit, one_fit_note);
  // Each detector alone on the photo (auto above: HOG, as it finds the face).
  for (DetectorChoice choice : {DetectorChoice::hog, DetectorChoice::cnn}) {
    DetectionOptions options;
    options.detector = choice;
    bench_one(detector, photo, crop_size, repeats, out, options);
  }
}

}  // namespace facetool
