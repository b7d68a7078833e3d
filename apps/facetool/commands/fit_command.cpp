// `facetool fit`: the ICT-FaceKit model fitted to every face's landmarks, its normals, depth,
// mask, visibility, textured mesh and parameters written at the photo's resolution (docs/fit.md).
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/output_option.h"
#include "apps/facetool/infer/photo_options.h"
#include "libs/photo/photo_pipeline.h"
#include "libs/face/photo_reader.h"
#include "apps/facetool/fit/fit_options.h"
#include "libs/fit/photo_fit.h"
#include "core/util/shard.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "core/util/folder_lock.h"
#include "core/util/output_names.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

struct PhotoJob {
  std::string path, folder;
  std::vector<DetectedFace> faces;  // largest first; empty: the photo failed
};

// Reads the photo and finds its faces; prints why and returns false when there is none.
bool detect_photo(PhotoJob& job, FaceDetector& detector, const DetectionOptions& detection, RgbImage& photo) {
  try {
    photo = read_photo(job.path);
  } catch (const Error& e) {
    std::cerr << "\nphoto '" << job.path << "': " << e.what() << "\n";
    return false;
  }
  job.faces = order_faces_by_size(detector.detect(photo, detection));
  if (job.faces.empty()) {
    std::cerr << "\nphoto '" << job.path << "': " << no_face_reason(photo, detection) << "\n";
    return false;
  }
  return true;
}

int run_fit(CommandContext&, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("face-model", po::value<std::string>()->value_name("DIR"),
       "the ICT-FaceKit FaceXModel folder (with vertex_indices.json)")
      ("same-person", "all photos show one person: one identity shared by every photo's main (largest) face")
      ("still-head", "all photos show one still head from one camera, e.g. under several lights: one identity, "
                     "pose and expression shared by every photo's main face (photos of one size)")
      ("shard", po::value<std::string>()->default_value("0/1")->value_name("i/n"),
       "fit only the inputs i, i+n, i+2n, ... (Slurm array jobs; same names as unsharded)")
      ("no-contact-sheet", "do not write contact_sheet.png");
  add_fit_options(options);
  add_photo_detection_options(options);
  po::options_description hidden;
  std::string out_dir;
  add_output_option(options, hidden, &out_dir, "DIR", "output folder (one sub-folder per photo)");
  hidden.add_options()("images", po::value<std::vector<std::string>>(), "input photos");
  po::positional_options_description positional;
  positional.add("images", -1);
  po::variables_map values;
  if (!parse_command_options(
          "fit PHOTO|DIR... --face-model DIR -o DIR [options]",
          "Finds every face in each photo (folders: every photo in them), fits the ICT-FaceKit "
          "model to its 68\nlandmarks (camera, pose, 60 identity and 53 expression weights) and "
          "renders the fit at the photo's\nresolution. Per photo, <output>/<name>/ holds the "
          "largest face's normal.exr (unit normals, camera\nframe: +X right, +Y up, +Z to the "
          "viewer; 0 where the mesh does not cover the pixel), depth.exr,\nvisibility.exr (9 SH "
          "coefficients), mask.png (the face region), mesh.obj + mesh.mtl + texture.png\n(the "
          "photo through projected UVs), fit.json (camera, pose, coefficients) and "
          "contact_sheet.png;\nface k > 0 gets the same in face_<k>/. A photo without a face is "
          "reported and skipped; the exit\nstatus is 1 if any photo failed (docs/fit.md). The "
          "landmark model (dlib, iBUG 300-W training data)\nis for research use only: no "
          "commercial use.",
          options, positional, args, values, hidden))
    return 0;
  std::vector<OptionRange> ranges = fit_option_ranges();
  for (const OptionRange& range : photo_option_ranges()) ranges.push_back(range);
  check_option_ranges(values, ranges);
  if (!values.count("images")) throw UsageError("fit: no input photos given");
  check_output_option(values, "fit", "an output folder with -o DIR");
  if (!values.count("face-model"))
    throw UsageError(std::string("fit: give --face-model DIR: ") + kIctFaceKitHint);
  for (const char* joint : {"same-person", "still-head"})
    if (values.count(joint) && values["shard"].as<std::string>() != "0/1")
      throw UsageError(std::string("fit: --") + joint +
                       " fits all the photos in one problem, so it cannot be split by --shard; run it unsharded");
  {
    std::error_code ec;
    check(!fs::exists(out_dir, ec) || fs::is_directory(out_dir, ec), "-o '", out_dir,
          "' is a file, not a folder; give a folder for the outputs");
  }
  PhotoFitOptions fit_options = fit_options_from(values);
  fit_options.contact_sheet = !values.count("no-contact-sheet");
  const PhotoInferOptions photo_options = photo_options_from(values);
  std::vector<std::string> files = expand_photo_inputs(values["images"].as<std::vector<std::string>>());
  // Output names come from the whole list, so shards write what one run writes.
  std::vector<PhotoJob> jobs;
  const std::vector<std::string> stems = unique_output_names(files);
  for (size_t k = 0; k < files.size(); ++k) jobs.push_back({files[k], (fs::path(out_dir) / stems[k]).string(), {}});
  {
    std::vector<std::string> folders;
    for (const PhotoJob& job : jobs) folders.push_back(job.folder);
    check_inputs_outside_output_folders(files, folders, "-o " + out_dir);
  }
  int shard_index = 0, shard_count = 1;
  parse_shard(values["shard"].as<std::string>(), shard_index, shard_count);
  if (shard_count > 1) {
    std::vector<PhotoJob> mine;
    for (size_t k = shard_index; k < jobs.size(); k += shard_count) mine.push_back(jobs[k]);
    check(!mine.empty(), "fit: shard ", values["shard"].as<std::string>(), " holds no inputs (fewer inputs than shards)");
    jobs = std::move(mine);
  }

  const auto basis = std::make_shared<const FitBasis>(FitBasis::load(values["face-model"].as<std::string>()));
  const PhotoFitter fitter(basis, fit_options);
  // One run per output folder (the shards of one sharded run write disjoint names and share it).
  {
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    check(!ec, "cannot create output folder '", out_dir, "': ", ec.message());
  }
  const FolderLock lock(out_dir, "-o", shard_index, shard_count);
  const std::unique_ptr<FaceDetector> face_detector = make_face_detector(photo_options);
  FaceDetector& detector = *face_detector;
  const bool still_head = values.count("still-head") > 0;
  const bool same_person = still_head || values.count("same-person") > 0;
  int failed = 0;
  PhotoFitTiming timing;
  std::map<size_t, FaceFit> joint;  // same person: job index -> its main face's fit
  if (same_person) {
    // First every photo's landmarks, then the one problem over all of them.
    ProgressBar landmarks("landmarks", static_cast<int64_t>(jobs.size()), "photos");
    std::vector<LandmarkTarget> targets;
    std::vector<size_t> owners;
    for (size_t k = 0; k < jobs.size(); ++k) {
      RgbImage photo;
      if (detect_photo(jobs[k], detector, photo_options.detection, photo)) {
        if (still_head && !targets.empty())
          check(photo.width == targets[0].width && photo.height == targets[0].height, "--still-head: photo '",
                jobs[k].path, "' is ", photo.width, "x", photo.height, " but '", jobs[owners[0]].path, "' is ",
                targets[0].width, "x", targets[0].height,
                "; one still head needs photos from one camera at one size (or use --same-person)");
        targets.push_back({jobs[k].faces[0].landmarks, photo.width, photo.height});
        owners.push_back(k);
      }
      landmarks.advance();
    }
    landmarks.finish();
    if (!targets.empty()) {
      const std::vector<FaceFit> fits = fit_landmarks(*basis, targets, fit_options.fit, still_head ? SharedFace::kHead : SharedFace::kIdentity);
      for (size_t i = 0; i < fits.size(); ++i) joint[owners[i]] = fits[i];
    }
  }
  ProgressBar progress("fit", static_cast<int64_t>(jobs.size()), "photos");
  for (size_t k = 0; k < jobs.size(); ++k) {
    PhotoJob& job = jobs[k];
    RgbImage photo;
    bool ok;
    if (same_person) {
      ok = joint.count(k) > 0;
      if (ok) photo = read_photo(job.path);
    } else {
      ok = detect_photo(job, detector, photo_options.detection, photo);
    }
    if (!ok) {
      ++failed;
      progress.advance();
      continue;
    }
    std::vector<FaceFit> fits = fitter.fit(photo, same_person ? std::vector<DetectedFace>(job.faces.begin() + 1, job.faces.end())
                                                              : job.faces);
    if (same_person) fits.insert(fits.begin(), joint[k]);
    fitter.write(job.folder, photo, job.faces, fits, job.path, &timing);
    progress.advance();
  }
  progress.finish();
  const size_t done = jobs.size() - failed;
  std::cerr << "wrote the fits of " << done << " of " << jobs.size() << " photos to " << out_dir << "\n";
  if (timing.faces > 0)
    std::cerr << "per face: fit " << 1e3 * timing.fit / timing.faces << " ms, rendering "
              << 1e3 * timing.geometry / timing.faces << " ms, visibility " << 1e3 * timing.visibility / timing.faces
              << " ms (" << timing.faces << " faces)\n";
  if (failed > 0) std::cerr << failed << " photo(s) failed (see above)\n";
  return failed > 0 ? 1 : 0;
}

const CommandRegistration registration{
    {"fit", "fit the ICT-FaceKit model to every face's landmarks: normals, depth, visibility, mesh", run_fit}};

}  // namespace
}  // namespace facetool
