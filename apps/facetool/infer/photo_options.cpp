// The photo options of `infer`, `relight` and `prepare-real`: detection, landmarks, paste-back.
#include "apps/facetool/infer/photo_options.h"

#include "core/util/error.h"

namespace po = boost::program_options;

namespace facetool {

void add_photo_detection_options(po::options_description& options) {
  options.add_options()
      ("detector", po::value<std::string>()->default_value("auto"), "face detector: hog, cnn, or auto (HOG, and dlib's CNN when HOG finds no face; docs/photos.md)")
      ("cnn-model", po::value<std::string>()->default_value(kDefaultCnnFaceModel), "dlib's CNN face detector model (mmod_human_face_detector.dat; scripts/install-dependencies.sh)")
      ("max-faces", po::value<int>()->default_value(0), "keep at most this many faces per photo, best detection score first (0: all)")
      ("min-face-size", po::value<double>()->default_value(0), "smallest face to find, photo pixels (0: max(80, shorter side / 8), and down to 40 on a photo of up to 640 pixels a side where none is found; docs/photos.md); a smaller value never finds fewer faces")
      ("min-score", po::value<double>()->default_value(0.25), "HOG detection score (margin) below which a box is not a face")
      ("min-cnn-score", po::value<double>()->default_value(0.0), "CNN detection score below which a box is not a face")
      ("pad", po::value<double>()->default_value(0.25), "before detection, pad the photo on every side by this fraction of its shorter side, in its mean colour, so faces filling the photo or cut by its edge are found")
      ("landmark-model", po::value<std::string>()->default_value(kDefaultLandmarkModel),
       "dlib 68-point shape predictor (Debian libdlib-data; trained on iBUG 300-W: research use only, no commercial use)")
      ("face-region", po::value<std::string>()->default_value("auto"), "the face's region (the mask; where results paste back): hull (the landmarks' convex hull), forehead (the hull over the forehead too), or auto (forehead at any framing but v1's; docs/photos.md)");
}

void add_photo_infer_options(po::options_description& options) {
  add_photo_detection_options(options);
  options.add_options()
      ("feather", po::value<double>()->default_value(3.0), "width of the blend at the mask's edge, crop pixels")
      ("upsample", po::value<std::string>()->default_value("guided"), "albedo and normals at the photo's resolution: guided (guided filter with the photo as guide) or bilinear (docs/photos.md)")
      ("transparent", "photo-level PNGs transparent outside the faces (default: the input photo there)");
}

std::vector<OptionRange> photo_option_ranges() {
  return {{"max-faces", 0, 10000},
          {"min-face-size", 0, 1e6},
          {"min-score", -10, 10},
          {"min-cnn-score", -10, 10},
          {"pad", 0, 2},
          {"feather", 0, 256}};
}

PhotoInferOptions photo_options_from(const po::variables_map& values) {
  PhotoInferOptions o;
  o.detection.max_faces = values["max-faces"].as<int>();
  o.detection.min_face_size = values["min-face-size"].as<double>();
  o.detection.score_threshold = values["min-score"].as<double>();
  o.landmark_model = values["landmark-model"].as<std::string>();
  o.detection.detector = parse_detector_choice(values["detector"].as<std::string>());
  o.cnn_model = values["cnn-model"].as<std::string>();
  o.detection.cnn_score_threshold = values["min-cnn-score"].as<double>();
  o.detection.padding = values["pad"].as<double>();
  o.region = parse_face_region(values["face-region"].as<std::string>(), "--face-region");
  if (values.count("feather")) o.feather = values["feather"].as<double>();
  if (values.count("upsample")) {
    const std::string upsample = values["upsample"].as<std::string>();
    if (upsample == "guided") o.upsample = Upsample::kGuided;
    else if (upsample == "bilinear") o.upsample = Upsample::kBilinear;
    else fail("--upsample must be guided or bilinear, not '", upsample, "'");
  }
  o.transparent = values.count("transparent") > 0;
  if (o.detection.max_faces < 0) fail("--max-faces must be 0 (all) or more");
  if (o.detection.min_face_size < 0) fail("--min-face-size must be 0 (automatic) or more");
  if (o.feather < 0) fail("--feather must be 0 or more");
  return o;
}

}  // namespace facetool
