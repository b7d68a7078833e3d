// `facetool infer`: face crops in; albedo, normal, visibility, light, shading, reconstruction out.
#include <filesystem>
#include <iostream>
#include <memory>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/output_option.h"
#include "apps/facetool/commands/component_images.h"
#include "libs/photo/decomposition_files.h"
#include "apps/facetool/infer/aligned_input.h"
#include "apps/facetool/infer/network_loading.h"
#include "apps/facetool/infer/photo_options.h"
#include "apps/facetool/fit/fit_options.h"
#include "libs/fit/photo_fit.h"
#include "core/util/shard.h"
#include "core/backend/registry.h"
#include "libs/image/resize.h"
#include "libs/inference/batched_decomposition.h"
#include "libs/inference/decomposer.h"
#include "libs/photo/photo_files.h"
#include "libs/photo/photo_outputs.h"
#include "libs/model/network_weights.h"
#include "libs/model/safetensors.h"
#include "libs/view/view_files.h"
#include "core/util/file_checks.h"
#include "core/util/folder_lock.h"
#include "core/util/output_names.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

int run_infer(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("batch", po::value<int>()->default_value(8), "images (face crops, from one photo or several) per network pass")
      ("shard", po::value<std::string>()->default_value("0/1")->value_name("i/n"),
       "decompose only the inputs i, i+n, i+2n, ... (Slurm array jobs; same names as unsharded)")
      ("renderer", po::value<std::string>()->default_value("sh_renderer"), "renderer plugin")
      ("contact-sheet", po::value<std::string>(), "with --aligned: contact sheet PNG (default: <output>/contact_sheet.png, with --shard i/n <output>/contact_sheet-<i>-of-<n>.png); photos get one each in their folder")
      ("no-contact-sheet", "do not write a contact sheet (as --outputs without contact-sheet)")
      ("outputs", po::value<std::string>()->value_name("LIST"),
       ("photos: write only these of each photo's files, and compute only what they need (comma-separated: " +
        PhotoOutputs::valid_names() +
        "; default all). albedo, normal, visibility, shading, reconstruction: that layer's PNG; exr: photo.exr; "
        "contact-sheet: contact_sheet.png; face-folders: the face_<k>/ folders; faces: faces.json, which is "
        "written whatever the list (where the faces are, and their lights)").c_str())
      ("raw-output", po::value<std::string>(), "with --aligned: also write the raw outputs (albedo, normal, visibility, light) of all images to this .safetensors file")
      ("aligned", "inputs are face crops, one face each: aligned by their landmarks when a face is found in the (padded) crop, otherwise stretched to the network's input (reported)")
      ("stretch", "with --aligned: stretch every crop to the network's input as it is, without looking for its landmarks (crops already in the network's framing, e.g. synth samples)")
      ("view", "also write view.html per photo and index.html in the output folder (`facetool view`, docs/viewer.md)")
      ("with-fit", "also fit the ICT-FaceKit model to every face and write `facetool fit`'s files in <name>/fit/ (docs/fit.md)");
  add_network_options(options);
  add_fit_options(options);
  add_photo_infer_options(options);
  po::options_description hidden;
  std::string out_dir;
  add_output_option(options, hidden, &out_dir, "DIR", "output folder (one sub-folder per image)");
  hidden.add_options()("images", po::value<std::vector<std::string>>(), "input images");
  po::positional_options_description positional;
  positional.add("images", -1);
  po::variables_map values;
  if (!parse_command_options(
          "infer PHOTO|DIR... [--model WEIGHTS | --init random] -o DIR [options]",
          "Finds every face in each photo (folders: every photo in them), aligns it to the "
          "synthetic framing,\ndecomposes it into albedo, normals, SH visibility and SH light, "
          "and pastes the results back at\nthe photo's resolution. Per photo, <output>/<name>/ "
          "holds albedo/normal/visibility/shading/\nreconstruction.png and photo.exr (all "
          "channels, alpha = face coverage), faces.json (boxes, scores,\nlandmarks, transforms, "
          "light in the photo's frame), contact_sheet.png (faces and landmarks\ndrawn) and one "
          "face_<k>/ folder per face with the crop-level files below; --outputs LIST\nwrites "
          "only those named (faces.json always) and skips the work the others need. A photo\nwithout a face "
          "is reported and skipped; the exit status is 1 if any photo failed (docs/photos.md).\n"
          "The landmark model (dlib, iBUG 300-W training data) is for research use only: no "
          "commercial use.\n\nWith --aligned the inputs are face crops, one face each: the best "
          "face found in the crop (padded\nas a photo is) is aligned by its landmarks like a "
          "photo's face; a crop without one is stretched\nto the network's input as it is, and "
          "said so (--stretch: every crop). Per image it writes\n<output>/<name>/: input.png, reconstruction.png, "
          "albedo.png/.exr, shading.png/.exr,\nnormal.png/.exr (PNG: (n+1)/2), visibility.png "
          "(ambient term)/.exr (9 channels), light.json, light.png.\nThe contact sheet shows per row: input, "
          "reconstruction, albedo, shading, normal, visibility.\n8-bit inputs are taken as sRGB "
          "and decoded to linear RGB; EXR/HDR inputs as linear.",
          options, positional, args, values, hidden))
    return 0;
  std::vector<OptionRange> ranges = network_option_ranges();
  ranges.push_back({"batch", 1, 1024});
  for (const OptionRange& range : photo_option_ranges()) ranges.push_back(range);
  for (const OptionRange& range : fit_option_ranges()) ranges.push_back(range);
  check_option_ranges(values, ranges);
  if (values.count("with-fit") && values.count("aligned")) throw UsageError("infer: --with-fit needs photos, not --aligned crops");
  if (values.count("with-fit") && !values.count("face-model"))
    throw UsageError(std::string("infer --with-fit: give --face-model DIR: ") + kIctFaceKitHint);

  if (!values.count("images")) throw UsageError("infer: no input images given");
  check_output_option(values, "infer", "an output folder with -o DIR");
  {
    std::error_code ec;
    check(!fs::exists(out_dir, ec) || fs::is_directory(out_dir, ec), "-o '", out_dir,
          "' is a file, not a folder; give a folder for the outputs");
  }
  if (values.count("contact-sheet") && !values.count("no-contact-sheet"))
    check_output_file_location(values["contact-sheet"].as<std::string>(), "--contact-sheet");
  if (values.count("raw-output"))
    check_output_file_location(values["raw-output"].as<std::string>(), "--raw-output");
  check_network_choice(values, "infer");
  const int batch = values["batch"].as<int>();
  if (batch < 1) throw UsageError("infer: --batch must be at least 1");
  const bool aligned = values.count("aligned") > 0;
  if (!aligned && values.count("raw-output")) throw UsageError("infer: --raw-output needs --aligned");
  if (!aligned && values.count("stretch")) throw UsageError("infer: --stretch needs --aligned");
  if (aligned && values.count("view")) throw UsageError("infer: --view needs photos, not --aligned crops");
  if (aligned && values.count("outputs")) throw UsageError("infer: --outputs needs photos, not --aligned crops");
  PhotoOutputs outputs;
  if (values.count("outputs")) {
    try {
      outputs = PhotoOutputs::parse(values["outputs"].as<std::string>(), "--outputs");
    } catch (const Error& e) {
      throw UsageError(std::string("infer: ") + e.what());
    }
  }
  if (values.count("view"))  // the page reads photo.exr, the layer PNGs and the face folders
    for (PhotoOutput needed : {PhotoOutput::kExr, PhotoOutput::kAlbedo, PhotoOutput::kNormal, PhotoOutput::kVisibility,
                               PhotoOutput::kShading, PhotoOutput::kReconstruction, PhotoOutput::kFaceFolders})
      if (!outputs.has(needed))
        throw UsageError("infer: --view reads photo.exr, the five layer PNGs and the face folders; --outputs '" +
                         values["outputs"].as<std::string>() + "' leaves some out (add exr,albedo,normal,visibility,"
                         "shading,reconstruction,face-folders, or leave out --view)");
  std::vector<std::string> files =
      aligned ? values["images"].as<std::vector<std::string>>()
              : expand_photo_inputs(values["images"].as<std::vector<std::string>>());
  for (const std::string& f : files) check_regular_input_file(f, kMaxImageFileBytes, "input image");
  // --contact-sheet and --raw-output name files: never one of the inputs.
  for (const char* option : {"contact-sheet", "raw-output"})
    if (values.count(option))
      check_output_is_not_an_input(values[option].as<std::string>(), std::string("--") + option,
                                   files);
  // Output names come from the whole list, so shards write what one run writes.
  std::vector<std::string> stems = unique_output_names(files);
  if (!aligned) {  // each photo's folder <-o>/<name>/ (its fit/ too) holds no input
    std::vector<std::string> folders;
    for (const std::string& stem : stems) folders.push_back((fs::path(out_dir) / stem).string());
    check_inputs_outside_output_folders(files, folders, "-o " + out_dir);
  }
  int shard_index = 0, shard_count = 1;
  parse_shard(values["shard"].as<std::string>(), shard_index, shard_count);
  if (shard_count > 1) {
    std::vector<std::string> mine, my_stems;
    for (size_t k : shard_positions(files.size(), shard_index, shard_count)) {
      mine.push_back(files[k]);
      my_stems.push_back(stems[k]);
    }
    check(!mine.empty(), "infer: shard ", values["shard"].as<std::string>(), " holds no inputs ",
          "(fewer inputs than shards)");
    files = std::move(mine);
    stems = std::move(my_stems);
  }
  PhotoInferOptions photo_options = photo_options_from(values);
  photo_options.batch = batch;
  photo_options.outputs = outputs;
  if (values.count("no-contact-sheet")) photo_options.outputs.remove(PhotoOutput::kContactSheet);
  photo_options.layers = photo_options.outputs.layers();  // only the layers the files read

  Backend& backend = get_backend(context.backend);
  const LoadedNetwork loaded = load_network(context, values, backend);
  photo_options.framing = loaded.framing;  // crops framed as the model was trained
  NetworkPlugin* network = loaded.network.get();
  const std::string& architecture = loaded.architecture;
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER,
                                                 values["renderer"].as<std::string>());
  Decomposer decomposer(*network, *renderer);
  apply_landmark_head_options(values, decomposer, loaded);
  apply_mirror_average_option(values, decomposer);
  // One run per output folder (the shards of one sharded run write disjoint names and share it).
  {
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    check(!ec, "cannot create output folder '", out_dir, "': ", ec.message());
  }
  const FolderLock lock(out_dir, "-o", shard_index, shard_count);
  const int size = network->config().input_size;
  // --face-model: loaded once for --with-fit and for a network that takes the fit's normals.
  const std::shared_ptr<const FitBasis> basis = load_face_model(values, loaded);
  photo_options.prior_basis = loaded.network->config().input_prior.empty() ? nullptr : basis.get();
  std::unique_ptr<PhotoFitter> fitter;
  if (values.count("with-fit")) {
    fitter = std::make_unique<PhotoFitter>(basis, fit_options_from(values));
    photo_options.with_fit = fitter.get();
  }
  if (!aligned) {
    const std::unique_ptr<FaceDetector> detector = make_face_detector(photo_options);
    PhotoDecomposer photo_decomposer(*detector, decomposer, backend, size, photo_options);
    int failed = infer_photos(files, stems, out_dir, photo_decomposer, photo_options);
    if (values.count("view")) {
      std::vector<std::string> folders;
      for (const std::string& stem : stems)
        if (fs::exists(fs::path(out_dir) / stem / "faces.json")) folders.push_back((fs::path(out_dir) / stem).string());
      view::ViewOptions view_options;
      view_options.feather = photo_options.feather;
      view_options.mask = photo_options.extends_forehead() ? view::MaskShape::kForehead : view::MaskShape::kHull;
      if (!folders.empty()) {
        failed += view::write_view_pages(folders, (fs::path(out_dir) / "index.html").string(), view_options);
        std::cerr << "view pages: " << (fs::path(out_dir) / "index.html").string() << "\n";
      }
    }
    std::cerr << "wrote the results of " << files.size() - failed << " of " << files.size()
              << " photos to " << out_dir << "\n";
    if (failed > 0) std::cerr << failed << " photo(s) failed (see above)\n";
    return failed > 0 ? 1 : 0;
  }

  // --aligned: the landmarks of each crop place it in the network's framing (--stretch: none).
  const std::unique_ptr<FaceDetector> detector =
      values.count("stretch") ? nullptr : make_face_detector(photo_options);
  std::vector<std::string> stretched;  // crops without a face found, in input order
  std::vector<RgbImage> sheet_rows;
  std::vector<float> raw_albedo, raw_normal, raw_visibility, raw_light;
  std::vector<float> batch_rgb;  // the batch's crops alone (the network's inputs may add a prior)
  std::vector<float> last_points;  // the landmarks of the crop loaded last, in crop pixels (none: stretched)
  ProgressBar progress("infer", static_cast<int64_t>(files.size()), "images");
  decompose_in_batches(
      decomposer, backend, files.size(), batch,
      [&](size_t k, std::vector<float>& inputs) {
        const AlignedInput input = read_aligned_input(files[k], size, detector.get(), photo_options);
        if (detector && !input.by_landmarks) {
          std::cerr << "\n'" << files[k] << "': " << input.reason << "; stretched to the network's input as it is\n";
          stretched.push_back(files[k]);
        }
        check(!photo_options.prior_basis || input.by_landmarks, "'", files[k], "': the model takes the fit of the face's ",
              "landmarks as input, and no landmarks were found in this crop (", input.reason.empty() ? "--stretch" : input.reason,
              "); leave it out or use a model without an input prior");
        const std::vector<float> one = network_inputs({input.crop}, network->config(), photo_options.prior_basis);
        if (inputs.empty()) batch_rgb.clear();
        inputs.insert(inputs.end(), one.begin(), one.end());
        batch_rgb.insert(batch_rgb.end(), input.crop.rgb.begin(), input.crop.rgb.end());
        last_points.clear();
        if (input.by_landmarks)
          for (const Point2& p : input.crop.alignment.crop_landmarks) {
            last_points.push_back(static_cast<float>(p.x));
            last_points.push_back(static_cast<float>(p.y));
          }
      },
      [&](size_t first, const Decomposition& d, const std::vector<float>&) {
        for (int i = 0; i < d.count; ++i) {
          write_decomposition((fs::path(out_dir) / stems[first + i]).string(), d, i, batch_rgb, files[first + i]);
          if (!values.count("no-contact-sheet")) sheet_rows.push_back(contact_sheet_row(d, i, batch_rgb));
        }
        if (values.count("raw-output")) {
          raw_albedo.insert(raw_albedo.end(), d.albedo.begin(), d.albedo.end());
          raw_normal.insert(raw_normal.end(), d.normal.begin(), d.normal.end());
          raw_visibility.insert(raw_visibility.end(), d.visibility.begin(), d.visibility.end());
          raw_light.insert(raw_light.end(), d.light.begin(), d.light.end());
        }
        progress.advance(d.count);
      },
      [&](size_t, std::vector<float>& points) {  // the crop's landmarks when it was aligned by them
        points.insert(points.end(), last_points.begin(), last_points.end());
        return !last_points.empty();
      });
  progress.finish();

  if (!sheet_rows.empty()) {
    // A shard's rows go to a sheet of its own (contact_sheet-<i>-of-<n>.png, like synth's
    // manifests), so shards writing into one folder do not overwrite each other's.
    const std::string default_name =
        shard_count > 1 ? "contact_sheet-" + std::to_string(shard_index) + "-of-" + std::to_string(shard_count) + ".png"
                        : std::string("contact_sheet.png");
    const std::string sheet = values.count("contact-sheet")
                                  ? values["contact-sheet"].as<std::string>()
                                  : (fs::path(out_dir) / default_name).string();
    write_png_atomically(sheet, stack_rows(sheet_rows));
    std::cerr << "contact sheet: " << sheet << "\n";
  }
  if (values.count("raw-output")) {
    const int64_t n = static_cast<int64_t>(files.size());
    SafeTensorsWriter raw;
    raw.set_metadata("format", "facetool-decomposition");
    raw.set_metadata("architecture", architecture);
    std::string list;
    for (const std::string& f : files) list += (list.empty() ? "" : "\n") + f;
    raw.set_metadata("images", list);
    raw.add("albedo", {n, 3, size, size}, std::move(raw_albedo));
    raw.add("normal", {n, 3, size, size}, std::move(raw_normal));
    raw.add("visibility", {n, 9, size, size}, std::move(raw_visibility));
    raw.add("light", {n, 27}, std::move(raw_light));
    raw.write_file(values["raw-output"].as<std::string>());
  }
  if (detector)
    std::cerr << "aligned " << files.size() - stretched.size() << " of " << files.size()
              << " crops by their landmarks; " << stretched.size()
              << " stretched to the network's input (no face found)\n";
  else
    std::cerr << "stretched " << files.size() << " crops to the network's input (--stretch)\n";
  std::cerr << "wrote " << files.size() << (files.size() == 1 ? " image's" : " images'")
            << " components to " << out_dir << "\n";
  return 0;
}

const CommandRegistration registration{
    {"infer", "decompose the faces of photos (or face crops) into albedo, normals, visibility and light", run_infer}};

}  // namespace
}  // namespace facetool
