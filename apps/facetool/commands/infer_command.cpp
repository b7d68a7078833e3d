// `facetool infer`: face crops in; albedo, normal, visibility, light, shading, reconstruction out.
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/component_images.h"
#include "apps/facetool/infer/infer_outputs.h"
#include "core/synth/synth_runner.h"
#include "core/backend/registry.h"
#include "core/image/resize.h"
#include "core/inference/decomposer.h"
#include "core/model/network_weights.h"
#include "core/model/safetensors.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

// One input crop: planar linear RGB at the network's size.
std::vector<float> load_crop(const std::string& path, int size) {
  const RgbImage image = read_rgb_image(path, !is_float_image_file(path));
  const size_t plane = static_cast<size_t>(image.width) * image.height;
  std::vector<float> planar(plane * 3);
  for (size_t p = 0; p < plane; ++p)
    for (int c = 0; c < 3; ++c) {
      const float v = image.pixels[p * 3 + c];
      check(std::isfinite(v), "image '", path, "' holds a NaN or infinite value");
      planar[c * plane + p] = v;
    }
  return resize_planar(planar, 3, image.width, image.height, size, size);
}

// Output folder names: the file's stem, made unique when two inputs share one.
std::vector<std::string> unique_stems(const std::vector<std::string>& files) {
  std::map<std::string, int> seen;
  std::vector<std::string> stems;
  for (const std::string& f : files) {
    std::string stem = fs::path(f).stem().string();
    const int n = ++seen[stem];
    stems.push_back(n == 1 ? stem : stem + "_" + std::to_string(n));
  }
  return stems;
}

int run_infer(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("model,m", po::value<std::string>(), "network weights (.safetensors, docs/model-format.md)")
      ("init", po::value<std::string>(), "'random': untrained weights instead of --model (for testing the pipeline)")
      ("seed", po::value<uint64_t>()->default_value(1), "seed of --init random")
      ("width", po::value<int>()->default_value(128), "network width for --init random")
      ("input-size", po::value<int>()->default_value(128), "network input size for --init random")
      ("output,o", po::value<std::string>(), "output folder (one sub-folder per image)")
      ("batch", po::value<int>()->default_value(8), "images per network pass")
      ("shard", po::value<std::string>()->default_value("0/1")->value_name("i/n"),
       "decompose only the inputs i, i+n, i+2n, ... (Slurm array jobs; same names as unsharded)")
      ("network", po::value<std::string>(), "network plugin (default: the weights' architecture, else paper_network)")
      ("renderer", po::value<std::string>()->default_value("sh_renderer"), "renderer plugin")
      ("contact-sheet", po::value<std::string>(), "contact sheet PNG (default: <output>/contact_sheet.png)")
      ("no-contact-sheet", "do not write a contact sheet")
      ("raw-output", po::value<std::string>(), "also write the raw outputs (albedo, normal, visibility, light) of all images to this .safetensors file");
  po::options_description hidden;
  hidden.add_options()("images", po::value<std::vector<std::string>>(), "input images");
  po::positional_options_description positional;
  positional.add("images", -1);
  po::variables_map values;
  if (!parse_command_options(
          "infer IMAGE... (--model WEIGHTS | --init random) -o DIR [options]",
          "Decomposes face crops (images already cropped to the face; they are resized to the "
          "network's input)\ninto albedo, normals, SH visibility and SH light, and renders them "
          "back. Per image it writes\n<output>/<name>/: input.png, reconstruction.png, "
          "albedo.png/.exr, shading.png/.exr,\nnormal.png/.exr (PNG: (n+1)/2), visibility.png "
          "(ambient term)/.exr (9 channels), light.json, light.png.\nThe contact sheet shows per row: input, "
          "reconstruction, albedo, shading, normal, visibility.\n8-bit inputs are taken as sRGB "
          "and decoded to linear RGB; EXR/HDR inputs as linear.",
          options, positional, args, values, hidden))
    return 0;
  check_option_ranges(values, {{"seed", 0, 18446744073709551615.0},
                               {"width", 1, 1024},
                               {"input-size", 2, 1024},
                               {"batch", 1, 1024}});

  if (!values.count("images")) throw UsageError("infer: no input images given");
  if (!values.count("output")) throw UsageError("infer: give an output folder with -o DIR");
  if (values.count("model") == values.count("init"))
    throw UsageError("infer: give exactly one of --model WEIGHTS or --init random");
  if (values.count("init") && values["init"].as<std::string>() != "random")
    throw UsageError("infer: --init takes only 'random'");
  const int batch = values["batch"].as<int>();
  if (batch < 1) throw UsageError("infer: --batch must be at least 1");
  std::vector<std::string> files = values["images"].as<std::vector<std::string>>();
  for (const std::string& f : files)
    check(fs::is_regular_file(f), "input image '", f, "' does not exist or is not a file");
  // Output names come from the whole list, so shards write what one run writes.
  std::vector<std::string> stems = unique_stems(files);
  int shard_index = 0, shard_count = 1;
  parse_shard(values["shard"].as<std::string>(), shard_index, shard_count);
  if (shard_count > 1) {
    std::vector<std::string> mine, my_stems;
    for (size_t k = shard_index; k < files.size(); k += shard_count) {
      mine.push_back(files[k]);
      my_stems.push_back(stems[k]);
    }
    check(!mine.empty(), "infer: shard ", values["shard"].as<std::string>(), " holds no inputs ",
          "(fewer inputs than shards)");
    files = std::move(mine);
    stems = std::move(my_stems);
  }
  const std::string out_dir = values["output"].as<std::string>();

  Backend& backend = get_backend(context.backend);
  std::shared_ptr<NetworkPlugin> network;
  std::string architecture = values.count("network") ? values["network"].as<std::string>() : "";
  if (values.count("model")) {
    const std::string path = values["model"].as<std::string>();
    const SafeTensors weights = SafeTensors::read_file(path);
    const WeightsHeader header = read_weights_header(weights, path);
    if (architecture.empty()) architecture = header.architecture;
    check(architecture == header.architecture, "weights '", path, "' are for network '",
          header.architecture, "' but --network asks for '", architecture, "'");
    network = create_plugin<NetworkPlugin>(context, FACETOOL_PLUGIN_NETWORK, architecture);
    network->build(backend, header.config);
    load_network_weights(*network, weights, path);
  } else {
    if (architecture.empty()) architecture = "paper_network";
    network = create_plugin<NetworkPlugin>(context, FACETOOL_PLUGIN_NETWORK, architecture);
    network->build(backend, NetworkConfig{values["width"].as<int>(), values["input-size"].as<int>()});
    network->init_random(values["seed"].as<uint64_t>());
  }
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER,
                                                 values["renderer"].as<std::string>());
  Decomposer decomposer(*network, *renderer);
  const int size = network->config().input_size;

  std::vector<RgbImage> sheet_rows;
  std::vector<float> raw_albedo, raw_normal, raw_visibility, raw_light;
  ProgressBar progress("infer", static_cast<int64_t>(files.size()), "images");
  for (size_t first = 0; first < files.size(); first += batch) {
    const int count = static_cast<int>(std::min(files.size() - first, static_cast<size_t>(batch)));
    std::vector<float> inputs;
    for (int i = 0; i < count; ++i) {
      std::vector<float> crop = load_crop(files[first + i], size);
      inputs.insert(inputs.end(), crop.begin(), crop.end());
    }
    const Decomposition d = decomposer.run(backend, inputs, count);
    for (int i = 0; i < count; ++i) {
      write_decomposition((fs::path(out_dir) / stems[first + i]).string(), d, i, inputs,
                          files[first + i]);
      if (!values.count("no-contact-sheet")) sheet_rows.push_back(contact_sheet_row(d, i, inputs));
    }
    if (values.count("raw-output")) {
      raw_albedo.insert(raw_albedo.end(), d.albedo.begin(), d.albedo.end());
      raw_normal.insert(raw_normal.end(), d.normal.begin(), d.normal.end());
      raw_visibility.insert(raw_visibility.end(), d.visibility.begin(), d.visibility.end());
      raw_light.insert(raw_light.end(), d.light.begin(), d.light.end());
    }
    progress.advance(count);
  }
  progress.finish();

  if (!sheet_rows.empty()) {
    const std::string sheet = values.count("contact-sheet")
                                  ? values["contact-sheet"].as<std::string>()
                                  : (fs::path(out_dir) / "contact_sheet.png").string();
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
  std::cerr << "wrote " << files.size() << (files.size() == 1 ? " image's" : " images'")
            << " components to " << out_dir << "\n";
  return 0;
}

const CommandRegistration registration{
    {"infer", "decompose face crops into albedo, normals, visibility and light", run_infer}};

}  // namespace
}  // namespace facetool
