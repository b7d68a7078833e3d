// `facetool unwrap`: fit-labelled real samples' albedo unwrapped into the neutral face's texture
// frame, for photo-textured synthetic faces (`synth --albedo-textures`).
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/fit/fit_options.h"
#include "core/util/file_checks.h"
#include "core/util/folder_lock.h"
#include "core/util/parallel_for.h"
#include "core/util/progress_bar.h"
#include "core/util/shard.h"
#include "libs/fit/albedo_unwrap.h"
#include "libs/io/exr_io.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

int run_unwrap(CommandContext&, const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string out_dir, shard = "0/1";
  int size = 128;
  options.add_options()
      ("face-model", po::value<std::string>()->value_name("DIR"), "the ICT-FaceKit FaceXModel folder (as for the labels)")
      ("output,o", po::value(&out_dir)->value_name("DIR")->required(), "output folder: one <sample name>.exr per sample")
      ("size", po::value(&size)->default_value(128), "texture size, texels per side")
      ("shard", po::value(&shard)->value_name("i/n")->default_value("0/1"),
       "unwrap only the inputs i, i+n, i+2n, ... (same file names as unsharded)");
  add_fit_options(options);
  po::options_description hidden;
  hidden.add_options()("samples", po::value<std::vector<std::string>>(), "inputs");
  po::positional_options_description positional;
  positional.add("samples", -1);
  po::variables_map values;
  if (!parse_command_options(
          "unwrap --face-model DIR SAMPLE.exr... -o DIR",
          "Unwraps each sample's albedo into the ICT neutral face's frontal texture frame: the fit of the\n"
          "sample's landmarks says which point of the face each pixel shows, and each pixel is de-lit by the\n"
          "shading of the sample's normals, visibility and light. Inputs: fit-labelled real samples\n"
          "(`facetool pseudo-label --from fit`) or synthetic ones. Each texture is an EXR (R G B albedo,\n"
          "A how much of it the photo saw); `synth --albedo-textures DIR` paints them on synthetic faces\n"
          "(docs/synthetic-data.md, \"Photo-textured albedo\"). Use the fit options the labels were made with.",
          options, positional, args, values, hidden))
    return 0;
  std::vector<OptionRange> ranges = fit_option_ranges();
  ranges.push_back({"size", 8, 1024});
  check_option_ranges(values, ranges);
  if (!values.count("face-model"))
    throw UsageError(std::string("unwrap: give --face-model DIR: ") + kIctFaceKitHint);
  if (!values.count("samples")) throw UsageError("unwrap: no samples given");
  std::vector<std::string> files = values["samples"].as<std::vector<std::string>>();
  for (const std::string& f : files) {
    check_regular_input_file(f, kMaxImageFileBytes, "sample");
    check(fs::path(f).extension() == ".exr", "sample '", f, "' is not an EXR: unwrap reads fit-labelled samples ",
          "(`facetool pseudo-label --from fit`) or synthetic ones");
  }
  // Textures are named after their samples: two inputs of one name would overwrite each other.
  std::map<std::string, std::string> owner;
  for (const std::string& f : files) {
    const auto [it, fresh] = owner.emplace(fs::path(f).filename().string(), f);
    check(fresh, "inputs '", it->second, "' and '", f, "' would both be written as '", it->first,
          "'; unwrap them into separate output folders");
  }
  int shard_index = 0, shard_count = 1;
  parse_shard(shard, shard_index, shard_count);
  std::vector<std::string> mine;
  for (size_t k : shard_positions(files.size(), shard_index, shard_count)) mine.push_back(files[k]);
  check(!mine.empty(), "unwrap: shard ", shard, " holds no inputs (fewer inputs than shards)");

  const PhotoFitOptions fit = fit_options_from(values);
  const FitBasis basis = FitBasis::load(values["face-model"].as<std::string>());
  const AlbedoTextureFrame frame = albedo_texture_frame(basis.model().neutral(), size);
  fs::create_directories(out_dir);
  check_input_folder(out_dir, "-o");
  const FolderLock lock(out_dir, "-o", shard_index, shard_count);
  for (const std::string& file : mine)
    check(!same_existing_file((fs::path(out_dir) / fs::path(file).filename()).string(), file), "-o '", out_dir,
          "' would replace the input '", file, "' with its texture; choose another -o");
  // Samples are independent (the basis and the frame are only read): all threads, the same files.
  ProgressBar progress("unwrap", static_cast<int64_t>(mine.size()), "samples");
  std::mutex progress_mutex;
  parallel_for_each_item(static_cast<int64_t>(mine.size()), [&](int64_t k) {
    const std::string& file = mine[static_cast<size_t>(k)];
    write_albedo_texture((fs::path(out_dir) / fs::path(file).filename()).string(),
                         unwrap_albedo(read_exr(file), file, basis, fit.fit, frame));
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress.advance();
  });
  progress.finish();
  std::cerr << "wrote " << mine.size() << " albedo textures (" << size << "x" << size << ") to " << out_dir << "\n";
  return 0;
}

const CommandRegistration registration{
    {"unwrap", "unwrap fit-labelled samples' albedo into the face's texture frame (photo-textured synth)",
     run_unwrap}};

}  // namespace
}  // namespace facetool
