// `facetool detect`: face detection and landmarks only, over photos and folders: a summary line
// per folder and, with --report, one CSV row per face (or per photo without one).
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/output_option.h"
#include "apps/facetool/infer/photo_options.h"
#include "libs/photo/photo_pipeline.h"
#include "libs/face/detection_summary.h"
#include "libs/face/face_detector.h"
#include "libs/face/photo_reader.h"
#include "core/util/atomic_file.h"
#include "core/util/file_checks.h"
#include "core/util/error.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

int run_detect(CommandContext&, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("report", po::value<std::string>(), "write a CSV: per face photo, face, detector, score, "
       "box, seconds, the 68 landmarks, how far apart the mirrored landmark fits were, whether "
       "they were retried, whether the face came from the brightened second look and whose box "
       "the landmarks were fitted in (hog or cnn); per photo without a face its reason");
  add_photo_detection_options(options);
  po::options_description hidden;
  hidden.add_options()("inputs", po::value<std::vector<std::string>>(), "photos and folders");
  po::positional_options_description positional;
  positional.add("inputs", -1);
  po::variables_map values;
  if (!parse_command_options(
          "detect PHOTO|DIR... [--report faces.csv] [options]",
          "Finds the faces and their 68 landmarks in photos, as infer and prepare-real do, and\n"
          "prints per folder how many photos had how many faces and which had none, and why\n"
          "(docs/photos.md). Folders give their image files (not recursive).",
          options, positional, args, values, hidden))
    return 0;
  check_option_ranges(values, photo_option_ranges());
  if (!values.count("inputs")) throw UsageError("detect: no photos or folders given");
  const std::vector<std::string> photos =
      expand_photo_inputs(values["inputs"].as<std::vector<std::string>>());
  const PhotoInferOptions photo = photo_options_from(values);
  if (values.count("report")) {
    check_output_file_location(values["report"].as<std::string>(), "--report");
    check_output_is_not_an_input(values["report"].as<std::string>(), "--report", photos);
  }

  FaceDetector detector(photo.landmark_model, photo.cnn_model);
  detector.prepare(photo.detection.detector);
  DetectionSummary summary;
  std::ostringstream csv;
  csv << std::setprecision(7)
      << "photo,face,detector,score,left,top,right,bottom,turned_deg,detect_s,landmark_s,reason";
  for (int i = 0; i < kLandmarkCount; ++i) csv << ",x" << i << ",y" << i;
  csv << ",landmark_disagreement,landmarks_retried,brightened,landmark_box\n";
  ProgressBar progress("detect", static_cast<int64_t>(photos.size()), "photos");
  for (const std::string& path : photos) {
    RgbImage image;
    try {
      image = read_photo(path);
    } catch (const Error& e) {
      std::cerr << "\nphoto '" << path << "': " << e.what() << "\n";
      summary.add(path, 0, "unreadable");
      csv << csv_field(path) << ",,,,,,,,,,,unreadable\n";
      progress.advance();
      continue;
    }
    const std::vector<DetectedFace> faces = detector.detect(image, photo.detection);
    const double seconds[2] = {detector.last_detection_seconds(), detector.last_landmark_seconds()};
    if (faces.empty()) {
      const std::string reason = no_face_reason(image, photo.detection);
      summary.add(path, 0, reason);
      csv << csv_field(path) << ",,,,,,,,," << seconds[0] << "," << seconds[1] << ","
          << csv_field(reason) << "\n";
    } else {
      summary.add(path, static_cast<int>(faces.size()));
    }
    for (size_t k = 0; k < faces.size(); ++k) {
      const DetectedFace& f = faces[k];
      csv << csv_field(path) << "," << k << "," << f.detector << "," << f.score << "," << f.left
          << "," << f.top << "," << f.right << "," << f.bottom << "," << f.rotation_deg << ","
          << seconds[0] << "," << seconds[1] << ",";
      for (const Point2& p : f.landmarks) csv << "," << p.x << "," << p.y;
      csv << "," << f.landmark_disagreement << "," << (f.landmarks_retried ? 1 : 0) << "," << (f.brightened ? 1 : 0)
          << "," << f.landmark_box << "\n";
    }
    progress.advance();
  }
  progress.finish();
  summary.print(std::cout);
  if (values.count("report")) {
    const std::string text = csv.str(), report = values["report"].as<std::string>();
    write_file_atomically(report, text.data(), text.size());
    std::cerr << "report: " << report << "\n";
  }
  return summary.photos_without_face() > 0 ? 1 : 0;
}

const CommandRegistration registration{
    {"detect", "find the faces and landmarks in photos; a summary per folder, --report CSV",
     run_detect}};

}  // namespace
}  // namespace facetool
