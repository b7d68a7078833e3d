// `facetool relight`: replace the light of the faces in photos, with self-shadowing (docs/relighting.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/light_rotation.h"
#include "apps/facetool/infer/network_loading.h"
#include "apps/facetool/infer/photo_options.h"
#include "libs/photo/photo_files.h"
#include "libs/photo/relight_pipeline.h"
#include "core/backend/registry.h"
#include "libs/face/face_detector.h"
#include "libs/light/direction_light.h"
#include "libs/light/light_formats.h"
#include "libs/relight/animated_gif.h"
#include "libs/light/environment_map_file.h"
#include "core/sh/sh_rotation.h"
#include "core/util/folder_lock.h"
#include "core/util/file_checks.h"
#include "core/util/output_names.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The new light from --light, --light-direction or --envmap (--light-from is handled once the
// source is decomposed).
sh::RgbLight light_from_file_options(const po::variables_map& values) {
  if (values.count("light-direction")) {
    const std::array<double, 2> angles = parse_azimuth_elevation(values["light-direction"].as<std::string>());
    return light::light_from_direction(angles[0], angles[1], values["ambient"].as<double>(),
                                       values["intensity"].as<double>());
  }
  if (values.count("light")) {
    const std::string path = values["light"].as<std::string>();
    check_regular_input_file(path, kMaxTextFileBytes, "light file");
    if (values.count("light-format")) {
      const light::Format format = light::format_from_name(values["light-format"].as<std::string>());
      return light::read_light(path, &format).light;
    }
    return light::read_light(path).light;
  }
  const std::string path = values["envmap"].as<std::string>();
  check_regular_input_file(path, kMaxImageFileBytes, "environment map");
  const sh::EnvironmentMap map = sh::read_environment_map(path);
  check(std::abs(map.width - 2 * map.height) <= 1, "environment map '", path, "' is ", map.width, "x",
        map.height, ", not an equirectangular (latitude-longitude) panorama, which is twice as wide "
        "as high; give a 2:1 .hdr or .exr panorama");
  return sh::project_environment_map(map);
}

void write_png_file(const fs::path& path, const RgbImage& image) { write_png_atomically(path.string(), image); }

int run_relight(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("light,l", po::value<std::string>(), "new light: a light file (facetool .json, SfSNet 27 values, DPR 9 values)")
      ("light-format", po::value<std::string>(), "format of --light: facetool, sfsnet or dpr (default: guessed from the file)")
      ("light-from", po::value<std::string>(), "light transfer: the light estimated on this photo's best face")
      ("envmap", po::value<std::string>(), "new light: an equirectangular environment map (.hdr, .exr), projected to SH")
      ("light-direction", po::value<std::string>()->value_name("AZ,EL"),
       "new light: a distant white light from azimuth AZ and elevation EL in degrees, in the photo's frame: 0,0 is "
       "the camera's position, a positive azimuth moves the light to the viewer's right, a positive elevation up; "
       "it shades a surface facing it --intensity above --ambient, as `light from-direction` (write "
       "--light-direction=-40,10 for a negative azimuth)")
      ("ambient", po::value<double>()->default_value(0.1, "0.1"), "the uniform light beside --light-direction, in the same units")
      ("rotate", po::value<std::string>()->value_name("YAW,PITCH,ROLL"),
       "turn the new light by these angles in degrees, as `light from-envmap --rotate` (write --rotate=-30,0,0 for a negative yaw)")
      ("intensity", po::value<double>()->default_value(1.0),
       "multiply the new light by this factor (with --light-direction: the distant light's strength, beside --ambient)")
      ("mode", po::value<std::string>()->default_value("ratio"),
       "ratio: photo x new shading / old shading (keeps the photo's detail); render: albedo x new shading")
      ("ratio-epsilon", po::value<double>()->default_value(relight::kDefaultRatioEpsilon, "0.02"),
       "guard of the ratio: (new + e) / (old + e), shading units")
      ("no-visibility", "also render with the open hemisphere (no self-shadowing), side by side with the result")
      ("orbit", po::value<int>()->default_value(0), "turn the light once around the head in N frames: frames + animated GIF")
      ("fps", po::value<int>()->default_value(12), "frames per second of the --orbit GIF")
      ("sheet-height", po::value<int>()->default_value(256), "height of each picture in sheet.png")
      ("timing", "print the time of the decomposition and of each further light (render + paste-back)")
      ("output,o", po::value<std::string>(), "output folder (one sub-folder per photo)")
      ("batch", po::value<int>()->default_value(8), "faces per network pass")
      ("renderer", po::value<std::string>()->default_value("sh_renderer"), "renderer plugin");
  options.add_options()
      ("feather", po::value<double>()->default_value(3.0), "width of the blend at the mask's edge, crop pixels");
  add_network_options(options);
  add_photo_detection_options(options);
  po::options_description hidden;
  hidden.add_options()("photos", po::value<std::vector<std::string>>(), "target photos");
  po::positional_options_description positional;
  positional.add("photos", -1);
  po::variables_map values;
  if (!parse_command_options(
          "relight PHOTO|DIR... (--light L | --light-from PHOTO2 | --light-direction AZ,EL | --envmap MAP) [--model W | --init random] -o DIR [options]",
          "Decomposes every face of each photo once, replaces its light by the new one and re-renders it\n"
          "with the estimated visibility (so nostrils, eye sockets and mouth keep their self-shadowing),\n"
          "then pastes it back into the photo at the photo's resolution. The new light is given in the\n"
          "photo's frame (+X right, +Y up, +Z towards the viewer). Per photo <output>/<name>/ holds\n"
          "relit.png, shading.png (estimated), relit_shading.png (new), light.json (new light),\n"
          "sheet.png (source or light sphere, photo, shading, new shading, result), with --no-visibility\n"
          "relit_no_visibility.png, with --orbit N orbit/frame_NNN.png and orbit.gif. A photo without a\n"
          "face is reported and skipped; the exit status is 1 if any photo failed (docs/relighting.md).",
          options, positional, args, values, hidden))
    return 0;
  std::vector<OptionRange> ranges = network_option_ranges();
  for (const OptionRange& range : photo_option_ranges()) ranges.push_back(range);
  for (const OptionRange& range : std::vector<OptionRange>{{"intensity", 0, 1e6},
                                                           {"ratio-epsilon", 1e-6, 10},
                                                           {"ambient", 0, 1e6},
                                                           {"orbit", 0, 3600},
                                                           {"fps", 1, 100},
                                                           {"sheet-height", 16, 4096},
                                                           {"batch", 1, 1024}})
    ranges.push_back(range);
  check_option_ranges(values, ranges);

  if (!values.count("photos")) throw UsageError("relight: no target photos given");
  if (!values.count("output")) throw UsageError("relight: give an output folder with -o DIR");
  const int sources = static_cast<int>(values.count("light") + values.count("light-from") + values.count("envmap") +
                                       values.count("light-direction"));
  if (sources != 1)
    throw UsageError("relight: give exactly one of --light FILE, --light-from PHOTO, --light-direction AZ,EL or --envmap MAP");
  if (!values["ambient"].defaulted() && !values.count("light-direction"))
    throw UsageError("relight: --ambient goes with --light-direction");
  if (values.count("light-format") && !values.count("light"))
    throw UsageError("relight: --light-format goes with --light");
  check_network_choice(values, "relight");
  RelightSettings settings;
  try {
    settings.mode = relight::mode_from_name(values["mode"].as<std::string>());
  } catch (const Error& e) {
    throw UsageError(std::string("relight: ") + e.what());
  }
  settings.ratio_epsilon = static_cast<float>(values["ratio-epsilon"].as<double>());
  if (!(settings.ratio_epsilon > 0)) throw UsageError("relight: --ratio-epsilon must be above 0");
  const double intensity = values["intensity"].as<double>();
  if (!std::isfinite(intensity) || intensity < 0) throw UsageError("relight: --intensity must be 0 or more");
  const int orbit = values["orbit"].as<int>(), fps = values["fps"].as<int>();
  if (orbit < 0 || orbit > 3600) throw UsageError("relight: --orbit must be between 0 (none) and 3600 frames");
  if (fps < 1 || fps > 100) throw UsageError("relight: --fps must be between 1 and 100");
  const int sheet_height = values["sheet-height"].as<int>();
  if (sheet_height < 16 || sheet_height > 4096) throw UsageError("relight: --sheet-height must be between 16 and 4096");
  const int batch = values["batch"].as<int>();
  if (batch < 1) throw UsageError("relight: --batch must be at least 1");
  const bool with_open = values.count("no-visibility") > 0, timing = values.count("timing") > 0;
  std::optional<sh::Mat3> rotation;
  if (values.count("rotate")) rotation = rotation_from_yaw_pitch_roll(parse_rotation(values["rotate"].as<std::string>()));
  PhotoInferOptions photo_options = photo_options_from(values);
  photo_options.batch = batch;
  const std::vector<std::string> photos = expand_photo_inputs(values["photos"].as<std::vector<std::string>>());
  const fs::path out_dir = values["output"].as<std::string>();

  // Everything that can be checked before any network pass: no input (a photo, --light-from's)
  // in a folder this run writes, and the light files.
  {
    std::vector<std::string> inputs = photos, folders;
    if (values.count("light-from")) inputs.push_back(values["light-from"].as<std::string>());
    for (const std::string& stem : unique_output_names(photos)) folders.push_back((out_dir / stem).string());
    check_inputs_outside_output_folders(inputs, folders, "-o " + out_dir.string());
  }
  std::optional<sh::RgbLight> file_light;
  if (!values.count("light-from")) file_light = light_from_file_options(values);

  Backend& backend = get_backend(context.backend);
  const LoadedNetwork loaded = load_network(context, values, backend);
  photo_options.framing = loaded.framing;  // crops framed as the model was trained
  const std::shared_ptr<const FitBasis> basis = load_face_model(values, loaded);  // a model with an input prior
  photo_options.prior_basis = basis.get();
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, values["renderer"].as<std::string>());
  Decomposer decomposer(*loaded.network, *renderer);
  apply_landmark_head_options(values, decomposer, loaded);
  apply_mirror_average_option(values, decomposer);
  const int size = loaded.network->config().input_size;
  const std::unique_ptr<FaceDetector> detector = make_face_detector(photo_options);
  PhotoDecomposer photo_decomposer(*detector, decomposer, backend, size, photo_options);

  std::optional<DecomposedPhoto> source;
  sh::RgbLight light{};
  if (values.count("light-from")) {
    const std::string path = values["light-from"].as<std::string>();
    check_regular_input_file(path, kMaxImageFileBytes, "light source photo");
    source = photo_decomposer.decompose_file(path);
    light = source->photo_lights[0];  // the best-scoring face
  } else {
    light = *file_light;
  }
  if (rotation) light = sh::rotate_light(light, *rotation);
  // --intensity scales the new light; with --light-direction it is the distant light's own
  // strength (beside --ambient), as in `light from-direction`.
  if (!values.count("light-direction")) light = relight::scale_light(light, intensity);

  // One run per output folder, from the first write on (a run refused on its light writes none).
  {
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    check(!ec, "cannot create output folder '", out_dir.string(), "': ", ec.message());
  }
  const FolderLock lock(out_dir.string(), "-o");  // one run per output folder
  const std::vector<std::string> stems = unique_output_names(photos);
  int failed = 0;
  ProgressBar progress("relight", static_cast<int64_t>(photos.size()), "photos");
  for (size_t index = 0; index < photos.size(); ++index) {
    const std::string& path = photos[index];
    const std::string& stem = stems[index];
    const Clock::time_point start = Clock::now();
    DecomposedPhoto target;
    try {
      target = photo_decomposer.decompose_file(path);
    } catch (const Error& e) {
      std::cerr << "\n" << e.what() << "\n";
      ++failed;
      progress.advance();
      continue;
    }
    const double decompose_s = seconds_since(start);
    const Clock::time_point render_start = Clock::now();
    const RelitPhoto relit = relight_photo(target, light, settings, *renderer, backend);
    const double relight_s = seconds_since(render_start);

    const fs::path folder = out_dir / stem;
    std::error_code ec;
    fs::create_directories(folder, ec);
    check(!ec, "cannot create output folder '", folder.string(), "': ", ec.message());
    write_png_file(folder / "relit.png", relit.image);
    const RgbImage old_shading = shading_over_photo(target, estimated_shading(target));
    const RgbImage new_shading = shading_over_photo(target, relit.new_shading);
    write_png_file(folder / "shading.png", old_shading);
    write_png_file(folder / "relit_shading.png", new_shading);
    light::LightFile light_file;
    light_file.light = light;
    light_file.metadata["created_by"] = "facetool relight";
    light_file.metadata["frame"] = "photo (+X right, +Y up, +Z towards the viewer)";
    light::write_light((folder / "light.json").string(), light_file, light::Format::Facetool);

    const RgbImage first = source ? source->photo : light_sphere(light, sheet_height);
    std::vector<RgbImage> tiles = {first, target.photo, old_shading, new_shading, relit.image};
    if (with_open) {
      RelightSettings open = settings;
      open.visibility = false;
      const RelitPhoto no_visibility = relight_photo(target, light, open, *renderer, backend);
      write_png_file(folder / "relit_no_visibility.png", no_visibility.image);
      tiles.push_back(no_visibility.image);
    }
    write_png_file(folder / "sheet.png", side_by_side(tiles, sheet_height));

    if (orbit > 0) {
      const fs::path frames_dir = folder / "orbit";
      fs::create_directories(frames_dir, ec);
      check(!ec, "cannot create output folder '", frames_dir.string(), "': ", ec.message());
      std::vector<RgbImage> frames;
      const int sphere = std::max(16, std::min(target.photo.width, target.photo.height) / 5);
      const Clock::time_point orbit_start = Clock::now();
      double render_s = 0;
      ProgressBar orbit_progress("orbit", orbit, "frames");
      for (int k = 0; k < orbit; ++k) {
        const sh::RgbLight frame_light = relight::orbit_light(light, k, orbit);
        const Clock::time_point frame_start = Clock::now();
        RgbImage frame = relight_photo(target, frame_light, settings, *renderer, backend).image;
        render_s += seconds_since(frame_start);
        draw_light_sphere(frame, frame_light, sphere);
        char name[32];
        std::snprintf(name, sizeof(name), "frame_%03d.png", k);
        write_png_file(frames_dir / name, frame);
        frames.push_back(std::move(frame));
        orbit_progress.advance();
      }
      orbit_progress.finish();
      const double orbit_s = seconds_since(orbit_start);
      write_animated_gif((folder / "orbit.gif").string(), frames, fps);
      if (timing)
        std::cerr << "\n" << path << ": orbit of " << orbit << " frames: " << render_s / orbit
                  << " s per frame to relight (render + paste-back), " << orbit_s / orbit
                  << " s with the light's sphere and the PNG write\n";
    }
    if (timing)
      std::cerr << "\n" << path << " (" << target.photo.width << "x" << target.photo.height << ", "
                << target.crops.size() << " face(s)): decomposition (read, detect, align, network) "
                << decompose_s << " s; relighting (render + paste-back) " << relight_s
                << " s; end to end " << decompose_s + relight_s << " s\n";
    progress.advance();
  }
  progress.finish();
  std::cerr << "relit " << photos.size() - failed << " of " << photos.size() << " photos into " << out_dir.string() << "\n";
  if (failed > 0) std::cerr << failed << " photo(s) failed (see above)\n";
  return failed > 0 ? 1 : 0;
}

const CommandRegistration registration{
    {"relight", "relight the faces of photos with a new light (file, envmap or another photo's), keeping self-shadowing", run_relight}};

}  // namespace
}  // namespace facetool
