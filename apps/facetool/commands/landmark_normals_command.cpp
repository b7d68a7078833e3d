// `facetool landmark-normals`: fits the landmark normal head to labelled samples and writes weights that carry it.
#include <filesystem>
#include <iostream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "core/util/file_checks.h"
#include "core/util/progress_bar.h"
#include "libs/data/training_sample.h"
#include "libs/image/crop_framing.h"
#include "libs/model/default_model.h"
#include "libs/model/landmark_normals.h"
#include "libs/model/network_weights.h"
#include "libs/model/safetensors.h"

namespace fs = std::filesystem;
namespace po = boost::program_options;

namespace facetool {
namespace {

std::vector<std::string> sample_files(const std::string& folder) {
  std::vector<std::string> problems;
  std::vector<std::string> files = list_folder_files(
      folder, "landmark-normals: data folder",
      [](const std::string& name) { return name.rfind("sample_", 0) == 0 && fs::path(name).extension() == ".exr"; },
      problems);
  check(problems.empty(), "landmark-normals: sample ", problems.empty() ? "" : problems[0], "; fix or remove it");
  check(!files.empty(), "landmark-normals: '", folder, "' holds no sample_*.exr files");
  return files;
}

int run_landmark_normals(CommandContext&, const std::vector<std::string>& args) {
  std::vector<std::string> data;
  std::string model, out;
  po::options_description options("Options");
  options.add_options()
      ("data", po::value(&data)->multitoken()->required()->value_name("DIR..."),
       "folders of labelled samples: real ones (prepare-real, then pseudo-label --from fit) and synthetic ones "
       "(synth); their facetool:landmarks, normals and mask")
      ("model,m", po::value(&model)->value_name("WEIGHTS"), "the network weights to carry the head (default: the shipped model)")
      ("output,o", po::value(&out)->required()->value_name("FILE"), "the weights written: the network's, with the head")
      ("grid", po::value<int>()->default_value(48), "cells per side of the head's normal map (a divisor of the crop size)")
      ("lambda", po::value<double>()->default_value(0.001), "ridge penalty on the weights")
      ("blend", po::value<double>()->default_value(0.85, "0.85"),
       "the head's weight against the network's normals inside the face (1: the head alone)");
  po::variables_map values;
  if (!parse_command_options(
          "landmark-normals --data DIR... [--model WEIGHTS] -o FILE",
          "Fits the landmark normal head (docs/model-card.md, \"The landmark normal head\"): a ridge\n"
          "regression from each crop's 68 landmarks (their coordinates and squares, after a similarity\n"
          "onto their mean) to a coarse map of its normals and mask, and writes the network's weights\n"
          "with the head beside them. The samples must be at the network's input size and framing.\n"
          "infer, relight, eval and the Python module then blend its normals into the network's\n"
          "(--no-landmark-normals: the network's alone). It needs no face model at run time.",
          options, po::positional_options_description{}, args, values))
    return 0;
  check_option_ranges(values, {{"grid", 1, 1024}, {"lambda", 0, 1e12}, {"blend", 0, 1}});
  if (model.empty()) model = default_model_path();
  const SafeTensors source = SafeTensors::read_file(model);
  const WeightsHeader header = read_weights_header(source, model);
  const int size = header.config.input_size;
  const int grid = values["grid"].as<int>();
  if (size % grid != 0)
    throw UsageError("landmark-normals: --grid " + std::to_string(grid) + " does not divide the network's input size " +
                     std::to_string(size));

  std::vector<std::string> files;
  for (const std::string& folder : data)
    for (std::string& f : sample_files(folder)) files.push_back(std::move(f));
  // Two passes: the landmarks' mean from the headers, then the faces moved onto it.
  std::vector<float> all_landmarks;
  for (const std::string& file : files) {
    const CropFraming framing = parse_framing(read_training_sample_framing(file), "sample '" + file + "'");
    check(framing == header.framing, "landmark-normals: sample '", file, "' is framed '", framing_text(framing),
          "' but the network takes '", framing_text(header.framing), "'; make samples of its size and framing");
    const std::vector<float> points = read_training_sample_landmarks(file);
    check(!points.empty(), "landmark-normals: sample '", file, "' has no facetool:landmarks (made by an older ",
          "prepare-real?)");
    all_landmarks.insert(all_landmarks.end(), points.begin(), points.end());
  }
  LandmarkNormalsFit fit(size, grid, mean_landmarks(all_landmarks));
  ProgressBar progress("landmark-normals", static_cast<int64_t>(files.size()), "samples");
  for (const std::string& file : files) {
    const TrainingSample s = read_training_sample(file, false);
    check(s.width == size && s.height == size, "landmark-normals: sample '", file, "' is ", s.width, "x", s.height,
          " but the network takes ", size, "x", size, "; make samples of its size and framing");
    check(s.labelled, "landmark-normals: real sample '", file, "' has no labels; label it with ",
          "`facetool pseudo-label --from fit --face-model DIR` first");
    fit.add(s.landmarks.data(), s.normal.data(), s.mask.data());
    progress.advance(1);
  }
  progress.finish();
  const LandmarkNormals head = fit.solve(values["lambda"].as<double>(), static_cast<float>(values["blend"].as<double>()));

  SafeTensorsWriter writer;  // the source's tensors and metadata, a former head replaced
  for (const auto& [key, value] : source.metadata())
    if (key != "landmark_normals") writer.set_metadata(key, value);
  for (const std::string& name : source.names())
    if (!is_landmark_normals_tensor(name)) writer.add(name, source.entry(name).shape, source.floats(name));
  add_landmark_normals(writer, head);
  writer.write_file(out);
  std::cerr << "fitted the landmark normal head (" << grid << "x" << grid << " cells, lambda " << head.lambda
            << ", blend " << head.blend << ") to " << fit.count() << " faces; wrote " << out << "\n";
  return 0;
}

const CommandRegistration registration{
    {"landmark-normals", "fit the landmark normal head to labelled samples and add it to weights",
     run_landmark_normals}};

}  // namespace
}  // namespace facetool
