// `facetool face-template`: derives the canonical 68-point template from the face model and
// prints it as the table in libs/face/face_template.cpp (docs/photos.md, "Template").
#include <iostream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "libs/face/face_template.h"
#include "libs/synth/landmark_projection.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

int run_face_template(CommandContext&, const std::vector<std::string>& args) {
  po::options_description options("Options");
  options.add_options()
      ("face-model", po::value<std::string>(), "ICT-FaceKit FaceXModel folder (with vertex_indices.json)")
      ("fov", po::value<double>()->default_value(22.5), "horizontal field of view, degrees (synth's mean)");
  po::variables_map values;
  if (!parse_command_options(
          "face-template --face-model DIR",
          "Projects the 68 landmark vertices of the neutral ICT face, posed and framed like a\n"
          "synthetic sample with zero rotation, through the synthetic camera, and prints them in\n"
          "crop units ((pixel centre + 0.5) / crop size) as C++ table rows.",
          options, po::positional_options_description{}, args, values))
    return 0;
  check_option_ranges(values, {{"fov", 1, 120}});
  if (!values.count("face-model")) throw UsageError("face-template: give --face-model DIR");
  const std::vector<std::array<double, 2>> projected = project_neutral_landmarks(
      values["face-model"].as<std::string>(), values["fov"].as<double>());
  Landmarks68 landmarks;
  for (int i = 0; i < kLandmarkCount; ++i) landmarks[i] = {projected[i][0], projected[i][1]};
  std::cout << template_table_source(landmarks);
  return 0;
}

const CommandRegistration registration{
    {"face-template", "print the canonical 68-point face template derived from the face model",
     run_face_template}};

}  // namespace
}  // namespace facetool
