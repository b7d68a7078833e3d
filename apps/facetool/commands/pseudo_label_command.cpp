// `facetool pseudo-label`: a trained network's albedo, normal, visibility and light written as
// labels into real face samples, so stage 2 reads them like synthetic ones.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/trained_model.h"
#include "apps/facetool/infer/network_loading.h"
#include "apps/facetool/fit/fit_options.h"
#include "libs/fit/fit_labels.h"
#include "libs/fit/fit_prior.h"
#include "libs/model/default_model.h"
#include "core/util/shard.h"
#include "core/backend/registry.h"
#include "libs/data/training_sample.h"
#include "libs/inference/batched_decomposition.h"
#include "libs/inference/decomposer.h"
#include "libs/inference/model_loading.h"
#include "libs/io/exr_io.h"
#include "core/plugin/renderer_plugin.h"
#include "libs/synth/synth_sample.h"
#include "core/util/file_checks.h"
#include "core/util/folder_lock.h"
#include "core/util/parallel_for.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

// The input's channels (labels replaced) plus the predicted ones; attributes kept, light_sh set.
LayeredImage labelled_sample(const FaceInput& in, const Decomposition& d, int index,
                             const std::string& model) {
  const int size = d.size;
  const size_t plane = static_cast<size_t>(size) * size;
  std::map<std::string, const float*> planes;  // name -> data, in the order written below
  std::vector<std::string> names;
  auto add = [&](const std::string& name, const float* data) {
    if (!planes.count(name)) names.push_back(name);
    planes[name] = data;
  };
  if (in.sample) {
    for (int c = 0; c < in.file.channel_count(); ++c) add(in.file.channel_names[c], in.file.plane(c));
  } else {
    const char* rgb[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) add(rgb[c], in.image.data() + c * plane);
    add("mask", in.mask.data());
  }
  const char* albedo[3] = {"albedo.R", "albedo.G", "albedo.B"};
  const char* normal[3] = {"normal.X", "normal.Y", "normal.Z"};
  for (int c = 0; c < 3; ++c) {
    add(albedo[c], d.albedo.data() + (static_cast<size_t>(index) * 3 + c) * plane);
    add(normal[c], d.normal.data() + (static_cast<size_t>(index) * 3 + c) * plane);
  }
  for (int j = 0; j < 9; ++j)
    add("visibility." + std::to_string(j),
        d.visibility.data() + (static_cast<size_t>(index) * 9 + j) * plane);
  LayeredImage out(size, size, names);
  for (size_t k = 0; k < names.size(); ++k)
    std::copy(planes[names[k]], planes[names[k]] + plane, out.plane(static_cast<int>(k)));
  if (in.sample) out.metadata = in.file.metadata;
  // Pseudo labels are not ground truth: the result is a real sample whatever the input was.
  out.set_metadata("facetool:generator_version", kRealSampleVersion);
  if (!out.find_metadata("facetool:source")) out.set_metadata("facetool:source", in.path);
  std::string light;
  char buffer[40];
  for (int k = 0; k < 27; ++k) {
    std::snprintf(buffer, sizeof buffer, "%.9g", d.light[static_cast<size_t>(index) * 27 + k]);
    light += (k ? " " : "") + std::string(buffer);
  }
  out.set_metadata("facetool:light_sh", light);
  out.set_metadata("facetool:pseudo_labels", model);
  return out;
}

// A sample's own seed for --landmark-noise: its name (FNV-1a), so that a rerun and every shard
// draw the same noise.
uint64_t name_seed(const std::string& file) {
  uint64_t h = 1469598103934665603ull;
  for (const unsigned char c : fs::path(file).filename().string()) h = (h ^ c) * 1099511628211ull;
  return h;
}

// --from fit: each sample with crop landmarks labelled by the fit to them (or, --prior-only,
// given the fit's normals as the network's input prior, its labels kept).
int pseudo_label_from_fit(const std::vector<std::string>& files, const std::string& out_dir,
                          int shard_index, int shard_count, const po::variables_map& values) {
  const bool prior_only = values.count("prior-only") != 0;
  const double noise = values["landmark-noise"].as<double>();
  const std::string mask_name = values["label-mask"].as<std::string>();
  const LabelMask mask = mask_name == "fitted" ? LabelMask::kFitted : LabelMask::kTrusted;
  const PhotoFitOptions options = fit_options_from(values);
  const FitBasis basis = FitBasis::load(values["face-model"].as<std::string>());
  const VisibilitySampler sampler(options.direction_count);
  fs::create_directories(out_dir);
  check_input_folder(out_dir, "-o");
  // One run per output folder (the shards of one sharded run write disjoint names and share it).
  const FolderLock lock(out_dir, "-o", shard_index, shard_count);
  for (const std::string& file : files)
    check(fs::path(file).extension() == ".exr", "input '", file, "' is not a sample EXR: pseudo-label --from fit ",
          "needs the samples of `facetool prepare-real` or `facetool synth` (their facetool:landmarks)");
  // Samples are independent (each its own fit, ray scene and file; the basis and the sampler are
  // only read), so they run on all threads: the same files as one after the other.
  ProgressBar progress("pseudo-label", static_cast<int64_t>(files.size()), "samples");
  std::mutex progress_mutex;
  parallel_for_each_item(static_cast<int64_t>(files.size()), [&](int64_t k) {
    const std::string& file = files[static_cast<size_t>(k)];
    const LayeredImage sample = read_exr(file);
    const std::string name = fs::path(file).filename().string();
    write_exr_atomically((fs::path(out_dir) / name).string(),
                         prior_only ? fit_prior_sample(sample, file, basis, options.fit, noise, name_seed(file))
                                    : fit_labelled_sample(sample, file, basis, options, sampler, "fit", mask));
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress.advance();
  });
  progress.finish();
  std::cerr << "wrote " << files.size() << (prior_only ? " samples with the fit's normals as input prior" : " fit-labelled samples")
            << " to " << out_dir << "\n";
  return 0;
}

// The file an input is written as: a sample EXR keeps its name, a plain crop is named after its
// position in the whole input list.
// (The same test as load_face_input's: an .exr with facetool's generator_version attribute.)
std::string output_name(const std::string& input, int64_t index) {
  if (fs::path(input).extension() == ".exr" &&
      read_exr_header(input, "facetool:").find_metadata("facetool:generator_version") != nullptr)
    return fs::path(input).filename().string();
  return sample_file_name(index);
}

int run_pseudo_label(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string model, out_dir, shard = "0/1", from = "network";
  int batch = 8;
  options.add_options()
      ("from", po::value(&from)->default_value("network")->value_name("network|fit"),
       "where the labels come from: the trained network, or the ICT-FaceKit fit to the samples' landmarks")
      ("face-model", po::value<std::string>()->value_name("DIR"), "--from fit: the ICT-FaceKit FaceXModel folder")
      ("prior-only", "--from fit: keep the samples' labels (synthetic ones, or network labels) and add only the "
       "fit's normals as the network's input prior (channels prior.X/Y/Z; no visibility is cast)")
      ("label-mask", po::value<std::string>()->default_value("trusted")->value_name("trusted|fitted"),
       "--from fit: the mask the labelled samples carry: trusted (where every label holds: the fitted face inside "
       "the sample's own mask, eroded by one pixel) or fitted (the whole fitted face region, beyond the photo's "
       "edge and the landmark hull, where the albedo label is 0: the shipped model's training labels)")
      ("landmark-noise", po::value<double>()->default_value(0.0)->value_name("F"),
       "--prior-only: move each landmark by a normal deviate of F x the inter-ocular distance in x and y before "
       "fitting (a detector's error, for synthetic samples, whose landmarks are exact; seeded by the file name)")
      ("model", po::value(&model)->value_name("WEIGHTS"),
       "trained weights (stage 1's weights.safetensors; default: the shipped model)")
      ("output,o", po::value(&out_dir)->value_name("DIR")->required(), "output folder")
      ("batch", po::value(&batch)->default_value(8), "images per network run")
      ("shard", po::value(&shard)->value_name("i/n")->default_value("0/1"),
       "label only the inputs i, i+n, i+2n, ... (Slurm array jobs; same file names as unsharded)");
  add_fit_options(options);
  add_mirror_average_option(options);
  add_landmark_head_options(options);
  po::options_description hidden;
  hidden.add_options()("images", po::value<std::vector<std::string>>(), "inputs");
  po::positional_options_description positional;
  positional.add("images", -1);
  po::variables_map values;
  if (!parse_command_options(
          "pseudo-label [--model WEIGHTS] INPUT... -o DIR",
          "Runs a trained network on real face samples and writes them to DIR with the predicted "
          "albedo, normal,\nvisibility and light as labels (channels albedo.*, normal.*, "
          "visibility.0..8, attribute facetool:light_sh),\nso that stage 2 reads them like "
          "synthetic samples. Inputs: sample EXRs of `facetool prepare-real`\n(kept whole, same "
          "file name, their mask used) or plain face crops (PNG/JPEG decoded from sRGB,\nresized; "
          "written as sample_<n>.exr in input order with a mask of 1 everywhere).\n\nWith --from fit "
          "(samples with crop landmarks: prepare-real's and synth's): the ICT-FaceKit model fitted to each sample's\nlandmarks gives "
          "the normals and visibility; light and a smooth albedo follow from the\nsample's pixels by "
          "least squares (docs/fit.md); the mask becomes the pixels all of them hold for (the fitted face\n"
          "inside the sample's own mask, eroded by one pixel; --label-mask).\nEvery fit-labelled sample also carries the fitted normals as "
          "the input prior of a network trained with network.input_prior \"fit_normal\" (channels prior.X/Y/Z);\n"
          "--prior-only adds just those, to synthetic samples (`synth` writes their landmarks) or labelled ones.",
          options, positional, args, values, hidden))
    return 0;
  std::vector<OptionRange> ranges = fit_option_ranges();
  ranges.push_back({"batch", 1, 1024});
  ranges.push_back({"landmark-noise", 0, 1});
  check_option_ranges(values, ranges);
  if (from != "network" && from != "fit") throw UsageError("pseudo-label: --from must be network or fit; got '" + from + "'");
  if (from == "fit" && !values.count("face-model"))
    throw UsageError(std::string("pseudo-label --from fit: give --face-model DIR: ") + kIctFaceKitHint);
  if (from == "fit" && values.count("model")) throw UsageError("pseudo-label: --model is for --from network");
  if (from != "fit" && values.count("prior-only")) throw UsageError("pseudo-label: --prior-only is for --from fit");
  if (values["label-mask"].as<std::string>() != "trusted" && values["label-mask"].as<std::string>() != "fitted")
    throw UsageError("pseudo-label: --label-mask must be trusted or fitted; got '" + values["label-mask"].as<std::string>() + "'");
  if (!values["label-mask"].defaulted() && (from != "fit" || values.count("prior-only")))
    throw UsageError("pseudo-label: --label-mask is for --from fit without --prior-only");
  if (!values.count("prior-only") && !values["landmark-noise"].defaulted())
    throw UsageError("pseudo-label: --landmark-noise is for --prior-only");
  if (!values.count("images")) throw UsageError("pseudo-label: no inputs given");
  if (model.empty() && from == "network") model = default_model_path();
  if (batch < 1) throw UsageError("pseudo-label: --batch must be at least 1");
  std::vector<std::string> files = values["images"].as<std::vector<std::string>>();
  for (const std::string& f : files) check_regular_input_file(f, kMaxImageFileBytes, "input");
  // The output names of the whole list (before sharding): two inputs never share one, and no
  // output replaces an input.
  std::map<std::string, size_t> owner;
  for (size_t k = 0; k < files.size(); ++k) {
    const std::string name = output_name(files[k], static_cast<int64_t>(k));
    const auto [it, fresh] = owner.emplace(name, k);
    check(fresh, "inputs '", files[it->second], "' and '", files[k], "' would both be written as '",
          name, "'; label them into separate output folders");
    check(!same_existing_file((fs::path(out_dir) / name).string(), files[k]), "-o '", out_dir,
          "' would replace the input '", files[k], "' with its labelled copy; choose another -o");
  }
  // Each input keeps its index in the whole list (plain crops are named sample_<index>.exr).
  int shard_index = 0, shard_count = 1;
  parse_shard(shard, shard_index, shard_count);
  std::vector<int64_t> index;
  std::vector<std::string> mine;
  for (size_t k : shard_positions(files.size(), shard_index, shard_count)) {
    mine.push_back(files[k]);
    index.push_back(static_cast<int64_t>(k));
  }
  check(!mine.empty(), "pseudo-label: shard ", shard, " holds no inputs (fewer inputs than shards)");
  files = std::move(mine);

  if (from == "fit") return pseudo_label_from_fit(files, out_dir, shard_index, shard_count, values);

  Backend& backend = get_backend(context.backend);
  const LoadedNetwork loaded = load_trained_network(context, backend, model);
  const std::shared_ptr<NetworkPlugin> network = loaded.network;
  check_takes_photos_alone(*network, model);
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, "sh_renderer");
  Decomposer decomposer(*network, *renderer);
  apply_mirror_average_option(values, decomposer);
  apply_landmark_head_options(values, decomposer, loaded);
  fs::create_directories(out_dir);
  check_input_folder(out_dir, "-o");
  // One run per output folder (the shards of one sharded run write disjoint names and share it).
  const FolderLock lock(out_dir, "-o", shard_index, shard_count);
  ProgressBar progress("pseudo-label", static_cast<int64_t>(files.size()), "images");
  std::vector<FaceInput> inputs;  // the batch's
  decompose_in_batches(
      decomposer, backend, files.size(), batch,
      [&](size_t k, std::vector<float>& planes) {
        if (planes.empty()) inputs.clear();
        inputs.push_back(load_face_input(files[k], loaded));
        planes.insert(planes.end(), inputs.back().image.begin(), inputs.back().image.end());
      },
      [&](size_t first, const Decomposition& d, const std::vector<float>&) {
        for (int i = 0; i < d.count; ++i) {
          const std::string name = output_name(files[first + i], index[first + i]);
          write_exr_atomically((fs::path(out_dir) / name).string(), labelled_sample(inputs[i], d, i, model));
        }
        progress.advance(d.count);
      },
      [&](size_t, std::vector<float>& points) {  // for the landmark normal head (the input just loaded)
        const std::vector<float>& own = inputs.back().landmarks;
        points.insert(points.end(), own.begin(), own.end());
        return !own.empty();
      });
  progress.finish();
  std::cerr << "wrote " << files.size() << " pseudo-labelled samples to " << out_dir << "\n";
  return 0;
}

const CommandRegistration registration{
    {"pseudo-label", "write a trained network's predictions as labels of real face samples (stage 2)",
     run_pseudo_label}};

}  // namespace
}  // namespace facetool
