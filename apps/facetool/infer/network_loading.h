// The network options shared by `infer` and `relight` (--model W, default the shipped model, or --init random), --no-mirror-average, --no-landmark-normals, --no-light-gain and --no-light-solve.
#pragma once

#include <boost/program_options.hpp>
#include <memory>
#include <string>
#include <vector>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "core/backend/backend.h"
#include "libs/inference/decomposer.h"
#include "libs/inference/model_loading.h"
#include "core/plugin/network_plugin.h"
#include "libs/fit/fit_basis.h"

namespace facetool {

// --model, --init, --seed, --width, --input-size, --network, --face-model, --no-mirror-average,
// --no-landmark-normals, --no-light-gain, --no-light-solve.
void add_network_options(boost::program_options::options_description& options);

// --no-mirror-average, and applying it: the commands that run a trained network average each
// crop's answer with its mirror image's unless told not to (libs/inference/mirror_average.h).
void add_mirror_average_option(boost::program_options::options_description& options);
void apply_mirror_average_option(const boost::program_options::variables_map& values, Decomposer& decomposer);

// --no-landmark-normals, --no-light-gain and --no-light-solve, and applying them: the weights' landmark normal head,
// if they carry one (libs/model/landmark_normals.h), and the light's gain fitted in its face mask
// (libs/inference/light_gain.h) are used unless told not to.
void add_landmark_head_options(boost::program_options::options_description& options);
void apply_landmark_head_options(const boost::program_options::variables_map& values, Decomposer& decomposer,
                                 const LoadedNetwork& loaded);

// Valid ranges of --seed, --width and --input-size (for check_option_ranges).
std::vector<OptionRange> network_option_ranges();

// Checks that --model and --init random are not both given (UsageError naming `command`).
void check_network_choice(const boost::program_options::variables_map& values, const std::string& command);

// Builds the weights' network on `backend` and loads them. `architecture` (a --network choice)
// must agree with the file's when given. Used by infer, relight, pseudo-label and eval.
LoadedNetwork load_network_weights_file(CommandContext& context, Backend& backend,
                                        const std::string& path, const std::string& architecture = "");

// Builds the network on `backend` from --model's weights, else the shipped model's
// (default_model.h; architecture from the file unless --network says otherwise, which must then
// agree), or with --init random weights. Weights that take the fit's normals as input need
// --face-model (UsageError otherwise).
LoadedNetwork load_network(CommandContext& context, const boost::program_options::variables_map& values,
                           Backend& backend);

// --face-model's ICT-FaceKit model when something needs it (--with-fit, or a network with an
// input prior), else null.
std::shared_ptr<const FitBasis> load_face_model(const boost::program_options::variables_map& values,
                                                const LoadedNetwork& loaded);

}  // namespace facetool
