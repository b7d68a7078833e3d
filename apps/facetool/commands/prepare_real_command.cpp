// `facetool prepare-real`: a real-photo dataset for stage 2 (aligned crops, masks, landmarks,
// transforms) in the sample layout the dataset reader reads; resumable; skipped photos with a
// reason in the manifest.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/infer/photo_options.h"
#include "libs/face/face_crops.h"
#include "libs/face/photo_reader.h"
#include "libs/face/real_sample.h"
#include "core/util/atomic_file.h"
#include "libs/io/exr_io.h"
#include "libs/io/sample_files.h"
#include "core/util/file_checks.h"
#include "core/util/folder_lock.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

struct Photo {
  std::string path;    // as found
  std::string source;  // relative to its input folder (the file name for a file argument)
};

// The photos of `inputs` (folders searched recursively, skipping the output folder `out` when it
// lies inside one: its samples are not inputs). Entries that cannot be read as files (dangling
// links, link loops, pipes) are added to `problems` with the reason.
std::vector<Photo> list_photos(const std::vector<std::string>& inputs, const std::string& out,
                               std::vector<std::pair<std::string, std::string>>& problems) {
  std::vector<Photo> photos;
  for (const std::string& input : inputs) {
    std::error_code input_error;
    if (fs::is_directory(input, input_error)) {
      std::vector<Photo> found;
      std::error_code ec;
      fs::recursive_directory_iterator it(input, ec), end;
      check(!ec, "input folder '", input, "' cannot be listed: ", ec.message());
      for (; it != end; it.increment(ec)) {
        check(!ec, "input folder '", input, "' cannot be listed: ", ec.message());
        const fs::directory_entry& e = *it;
        std::error_code same;
        if (e.is_directory(same) && fs::equivalent(e.path(), out, same)) {
          it.disable_recursion_pending();
          continue;
        }
        std::string ext = e.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return std::tolower(c); });
        const bool photo_name = ext == ".png" || ext == ".jpg" || ext == ".jpeg" ||
                                ext == ".tif" || ext == ".tiff" || ext == ".bmp" ||
                                ext == ".webp" || ext == ".exr" || ext == ".hdr";
        std::error_code status_error;
        const fs::file_status target = e.status(status_error);  // follows a link
        if (fs::is_directory(target) || !photo_name ||
            is_temporary_file_name(e.path().filename().string()))
          continue;
        if (!fs::is_regular_file(target)) {
          const std::string why =
              target.type() == fs::file_type::not_found ? "a symbolic link to nothing"
              : status_error ? status_error.message()
                             : std::string("not a regular file (a pipe, device or socket)");
          problems.emplace_back(fs::relative(e.path(), input).generic_string(),
                                "unreadable: " + why);
          continue;
        }
        found.push_back({e.path().string(), fs::relative(e.path(), input).generic_string()});
      }
      std::sort(found.begin(), found.end(), [](const Photo& a, const Photo& b) { return a.source < b.source; });
      check(!found.empty(), "folder '", input, "' holds no photos");
      photos.insert(photos.end(), found.begin(), found.end());
    } else {
      check_regular_input_file(input, kMaxImageFileBytes, "input photo");
      photos.push_back({input, fs::path(input).filename().generic_string()});
    }
  }
  return photos;
}

std::string clean(std::string text) {  // one TSV field
  std::replace(text.begin(), text.end(), '\t', ' ');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

int run_prepare_real(CommandContext&, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("output,o", po::value<std::string>(), "output folder (sample_XXXXXXXX.exr, manifest.tsv)")
      ("size", po::value<int>()->default_value(128), "crop size, pixels (the network's input)")
      ("max-edge-cut", po::value<double>()->default_value(0.05), "skip a face when more than this fraction of its mask lies outside the photo")
      ("framing", po::value<std::string>()->default_value("v1"), "crop framing: v1, v2, or 'zoom Z centre X Y border edge-repeat|ring-mean' (the model's; docs/photos.md, \"Framing\")");
  add_photo_detection_options(options);
  po::options_description hidden;
  hidden.add_options()("inputs", po::value<std::vector<std::string>>(), "photo folders");
  po::positional_options_description positional;
  positional.add("inputs", -1);
  po::variables_map values;
  if (!parse_command_options(
          "prepare-real DIR|PHOTO... -o REAL/ [options]",
          "Builds a real-photo dataset for stage 2 of training: per photo (folders are searched\n"
          "recursively, sorted by path) the best-scoring face is detected, aligned to the synthetic\n"
          "framing and written as REAL/sample_<k>.exr (k = the photo's position in the sorted list):\n"
          "channels R G B (linear; 8/16-bit photos are sRGB-decoded) and mask, attributes\n"
          "facetool:source, facetool:landmarks, facetool:transform (docs/photos.md). A rerun keeps\n"
          "the samples already written for the same photos. Photos without a usable face are\n"
          "listed in REAL/manifest.tsv with the reason. The landmark model (dlib, iBUG 300-W\n"
          "training data) is for research use only: no commercial use.",
          options, positional, args, values, hidden))
    return 0;
  std::vector<OptionRange> ranges = {{"size", 16, 1024}, {"max-edge-cut", 0, 1}};
  for (const OptionRange& range : photo_option_ranges()) ranges.push_back(range);
  check_option_ranges(values, ranges);
  if (!values.count("inputs")) throw UsageError("prepare-real: no input folders given");
  if (!values.count("output")) throw UsageError("prepare-real: give an output folder with -o DIR");
  const int size = values["size"].as<int>();
  if (size < 16) throw UsageError("prepare-real: --size must be at least 16");
  const double max_cut = values["max-edge-cut"].as<double>();
  PhotoInferOptions photo = photo_options_from(values);
  photo.detection.max_faces = 1;
  photo.framing = parse_framing(values["framing"].as<std::string>(), "--framing");
  const std::string out = values["output"].as<std::string>();
  std::error_code ec;
  fs::create_directories(out, ec);
  check(!ec, "cannot create output folder '", out, "': ", ec.message());
  check_input_folder(out, "-o");
  const FolderLock lock(out, "-o");  // one run per output folder
  std::vector<std::pair<std::string, std::string>> problems;
  const std::vector<Photo> photos =
      list_photos(values["inputs"].as<std::vector<std::string>>(), out, problems);
  remove_stale_temporary_files(out);

  FaceDetector detector(photo.landmark_model, photo.cnn_model);
  detector.prepare(photo.detection.detector);
  std::ostringstream manifest;
  std::ostringstream settings_line;
  settings_line << "# facetool prepare-real manifest: generator " << kRealSampleVersion
                << ", size " << size
                << (photo.extends_forehead() ? ", mask hull+forehead" : ", mask hull");
  if (photo.framing != CropFraming{}) settings_line << ", framing " << framing_text(photo.framing);
  const std::string settings = settings_line.str();
  // A rerun keeps the samples already there only when they were made with these settings.
  const std::string manifest_path = (fs::path(out) / "manifest.tsv").string();
  if (fs::exists(manifest_path)) {
    const std::string earlier =
        read_regular_input_file(manifest_path, kMaxTextFileBytes, "manifest");
    const std::string first_line = earlier.substr(0, earlier.find('\n'));
    check(first_line == settings, "-o '", out, "' holds samples made with other settings ('",
          first_line, "', now '", settings, "'); use a new output folder");
  }
  manifest << settings << "\n" << "file\tsource\tstatus\tdetail\n";
  int written = 0, kept = 0, skipped = 0;
  ProgressBar progress("prepare-real", static_cast<int64_t>(photos.size()), "photos");
  for (size_t k = 0; k < photos.size(); ++k) {
    const Photo& p = photos[k];
    const std::string name = sample_file_name(static_cast<int64_t>(k));
    const std::string path = (fs::path(out) / name).string();
    if (fs::exists(path)) {
      // Another kind of sample (synthetic, pseudo-labelled) is another dataset: never replaced.
      std::string version = "(unreadable)";
      try {
        const LayeredImage header = read_exr_header(path, "facetool:");
        const std::string* v = header.find_metadata("facetool:generator_version");
        version = v ? *v : "(none)";
        check(!v || *v != kRealSampleVersion || header.width == size, "'", path, "' is ",
              header.width, " pixels wide but --size is ", size,
              ": it was made with other settings; use a new output folder");
      } catch (const Error& e) {
        if (version != "(unreadable)") throw;
      }
      check(version == "(unreadable)" || version == kRealSampleVersion, "-o '", out,
            "' holds '", name, "', a sample of another kind (generator ", version,
            "): prepare-real would replace it; use a new output folder");
      const std::string source = read_real_sample_source(path);
      check(source.empty() || source == p.source, "'", path, "' holds the sample of '", source,
            "' but photo ", k, " is now '", p.source,
            "': the input photos changed since that run; use a new output folder");
      if (!source.empty()) {
        manifest << name << "\t" << clean(p.source) << "\tkept\t\n";
        ++kept;
        progress.advance();
        continue;
      }
    }
    std::string reason;
    try {
      const RgbImage image = read_photo(p.path);
      const std::vector<FaceCrop> faces = find_face_crops(detector, image, size, photo);
      if (faces.empty()) {
        reason = "no face found";
      } else {
        const FaceCrop& crop = faces[0];
        const double cut = mask_fraction_outside_photo(crop, image.width, image.height);
        if (cut > max_cut) {
          reason = "face cut by the photo's edge (" + std::to_string(static_cast<int>(cut * 100)) + "% of its mask outside)";
        } else {
          write_exr_atomically(path, real_sample_image(crop, p.source, photo.extends_forehead(), photo.framing));
          manifest << name << "\t" << clean(p.source) << "\twritten\tscore " << crop.face.score << "\n";
          ++written;
        }
      }
    } catch (const Error& e) {
      reason = std::string("unreadable: ") + e.what();
    }
    if (!reason.empty()) {
      if (fs::exists(path)) fs::remove(path);  // a damaged sample of this photo from a crash
      manifest << "-\t" << clean(p.source) << "\tskipped\t" << clean(reason) << "\n";
      ++skipped;
    }
    progress.advance();
  }
  progress.finish();
  for (const auto& [source, reason] : problems) {
    manifest << "-\t" << clean(source) << "\tskipped\t" << clean(reason) << "\n";
    ++skipped;
  }
  const std::string text = manifest.str();
  write_file_atomically((fs::path(out) / "manifest.tsv").string(), text.data(), text.size());
  std::cerr << "prepare-real: " << written << " written, " << kept << " kept from an earlier run, "
            << skipped << " skipped (reasons in " << (fs::path(out) / "manifest.tsv").string() << ")\n";
  return 0;
}

const CommandRegistration registration{
    {"prepare-real", "build a real-photo dataset (aligned crops, masks, landmarks) for training",
     run_prepare_real}};

}  // namespace
}  // namespace facetool
