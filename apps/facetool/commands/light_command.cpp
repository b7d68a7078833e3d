// `facetool light`: environment maps to SH lights, conversion between light formats, previews.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/output_option.h"
#include "apps/facetool/commands/light_rotation.h"
#include "libs/light/direction_light.h"
#include "libs/light/light_formats.h"
#include "libs/light/light_preview.h"
#include "libs/light/environment_map_file.h"
#include "core/sh/light_clamp.h"
#include "core/sh/sh_rotation.h"
#include "core/util/file_checks.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

const char kOverview[] =
    "usage: facetool light <subcommand> [options]\n\n"
    "SH lights (27 coefficients: R0..R8, G0..G8, B0..B8; docs/conventions.md):\n"
    "  from-envmap ENV.{hdr,exr} -o light.json   project an equirectangular environment map\n"
    "  from-direction AZ,EL -o light.json        a distant light from angles in degrees, plus ambient\n"
    "  convert IN OUT --to {facetool,sfsnet,dpr}  convert between light file formats\n"
    "  show LIGHT -o light.png                    picture: lit sphere + radiance panorama\n\n"
    "Run 'facetool light <subcommand> --help' for its options.\n";

void require_existing_file(const std::string& path, const std::string& what) {
  check_regular_input_file(path, kMaxImageFileBytes, what);  // its reader applies its own limit
}

std::string format_channel(const sh::RgbLight& light, int index) {
  char buffer[80];
  std::snprintf(buffer, sizeof(buffer), "%.6g %.6g %.6g", light[index], light[9 + index],
                light[18 + index]);
  return buffer;
}

int run_from_envmap(const std::vector<std::string>& args) {
  po::options_description options("Options");
  po::options_description hidden;
  std::string input, output, rotate;
  add_output_option(options, hidden, &output, "FILE.json", "facetool light file to write");
  options.add_options()
      ("rotate", po::value(&rotate)->value_name("YAW,PITCH,ROLL"),
       "turn the light by these angles in degrees: R = Ry(yaw) Rx(pitch) Rz(roll), each "
       "counter-clockwise about its axis (right-hand rule; +Y up, camera at +Z): light from w "
       "then arrives from R w. yaw +90 moves a light from the camera's side (+Z) to +X (the "
       "viewer's right), pitch +90 moves it from +Z to -Y (below), roll +90 moves +X to +Y. "
       "Write --rotate=-30,0,0 for a negative yaw")
      ("clamp", po::bool_switch(),
       "make the light non-negative on the sphere: project max(0, L(w)) back (64,000 "
       "directions)");
  hidden.add_options()("input", po::value(&input)->required(), "environment map");
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map values;
  if (!parse_command_options(
          "light from-envmap ENV.{hdr,exr} -o FILE.json [options]",
          "Projects an equirectangular environment map (HDR, EXR or any image OpenImageIO reads;\n"
          "linear radiance; top row up, centre = -Z = straight ahead of the camera, u = 3/4 is\n"
          "+X) onto the 9 SH per channel, each pixel weighted by its exact solid angle, and\n"
          "writes a facetool light JSON with the source file and rotation as metadata.",
          options, positional, args, values, hidden))
    return 0;
  check_option_ranges(values, {});  // no numeric options (a new one must get a range)
  check_output_option(values, "light from-envmap", "the light file to write with -o FILE.json");
  if (output.empty()) throw UsageError("-o FILE.json must not be empty");
  require_existing_file(input, "environment map");
  const std::array<double, 3> angles =
      rotate.empty() ? std::array<double, 3>{0, 0, 0} : parse_rotation(rotate);
  const bool clamp = values["clamp"].as<bool>();

  const sh::EnvironmentMap map = sh::read_environment_map(input);
  for (size_t i = 0; i < map.rgb.size(); ++i)
    check(std::isfinite(map.rgb[i]), "environment map '", input,
          "' holds a NaN or infinite value at pixel (", (i / 3) % map.width, ", ",
          (i / 3) / map.width, "); fix the map");
  sh::RgbLight light = sh::project_environment_map(map);
  if (!rotate.empty()) light = sh::rotate_light(light, rotation_from_yaw_pitch_roll(angles));
  if (clamp) light = sh::clamp_light_nonnegative(light);

  light::LightFile file;
  file.light = light;
  file.metadata["source"] = input;
  file.metadata["source_size"] = std::to_string(map.width) + "x" + std::to_string(map.height);
  char rotation[160];
  std::snprintf(rotation, sizeof(rotation),
                "yaw %.9g, pitch %.9g, roll %.9g degrees; R = Ry(yaw) Rx(pitch) Rz(roll)",
                angles[0], angles[1], angles[2]);
  file.metadata["rotation"] = rotation;
  file.metadata["clamped"] = clamp ? "true" : "false";
  file.metadata["created_by"] = "facetool light from-envmap";
  light::write_light(output, file, light::Format::Facetool);
  std::cout << "light: " << output << " (from " << input << ", " << map.width << "x"
            << map.height << ")\n"
            << "  L_0 (R G B): " << format_channel(light, 0) << "  (mean radiance x 2 sqrt(pi))\n";
  return 0;
}

int run_from_direction(const std::vector<std::string>& args) {
  po::options_description options("Options");
  po::options_description hidden;
  std::string angles_text, output;
  double ambient = 0.1, intensity = 1.0;
  add_output_option(options, hidden, &output, "FILE.json", "facetool light file to write");
  options.add_options()
      ("direction", po::value(&angles_text)->value_name("AZ,EL")->required(),
       "azimuth,elevation in degrees (or give them first, without the option); write --direction=-40,20 for a "
       "negative azimuth")
      ("ambient", po::value(&ambient)->default_value(0.1, "0.1"), "the uniform light beside the distant one")
      ("intensity", po::value(&intensity)->default_value(1.0, "1"),
       "the distant light's strength: a surface facing it is shaded this much above the ambient (albedo 1)");
  po::positional_options_description positional;
  positional.add("direction", 1);
  po::variables_map values;
  if (!parse_command_options(
          "light from-direction AZ,EL -o FILE.json [--ambient A] [--intensity I]",
          "Writes a white distant light from azimuth AZ and elevation EL (degrees, the photo's frame:\n"
          "0,0 is the camera's position, a positive azimuth moves the light to the viewer's right, a\n"
          "positive elevation up; for a negative azimuth write --direction=-40,20) plus a uniform ambient,\n"
          "as 27 SH coefficients: with albedo 1 and no occlusion a surface of normal n is shaded\n"
          "A + I max(0, n.l). `relight --light-direction AZ,EL --ambient A --intensity I` uses the same light.",
          options, positional, args, values, hidden))
    return 0;
  check_option_ranges(values, {{"ambient", 0, 1e6}, {"intensity", 0, 1e6}});
  check_output_option(values, "light from-direction", "the light file to write with -o FILE.json");
  if (output.empty()) throw UsageError("-o FILE.json must not be empty");
  const std::array<double, 2> angles = parse_azimuth_elevation(angles_text);
  light::LightFile file;
  file.light = light::light_from_direction(angles[0], angles[1], ambient, intensity);
  char text[200];
  std::snprintf(text, sizeof(text), "azimuth %.9g, elevation %.9g degrees; ambient %.9g, intensity %.9g", angles[0],
                angles[1], ambient, intensity);
  file.metadata["direction"] = text;
  file.metadata["created_by"] = "facetool light from-direction";
  light::write_light(output, file, light::Format::Facetool);
  const sh::Vec3 d = light::direction_from_angles(angles[0], angles[1]);
  std::printf("light: %s (towards (%.4f, %.4f, %.4f) in the photo's frame, +X right, +Y up, +Z to the viewer)\n",
              output.c_str(), d[0], d[1], d[2]);
  return 0;
}

int run_convert(const std::vector<std::string>& args) {
  po::options_description options("Options");
  po::options_description hidden;
  std::string input, output, to, from;
  options.add_options()
      ("to", po::value(&to)->value_name("FORMAT")->required(),
       "format to write: facetool (JSON), sfsnet (3 lines of 9), dpr (9 numbers, grey), "
       "rgb-table (9 lines of 'R G B', facetool's coefficients, as synth --lights reads)")
      ("from", po::value(&from)->value_name("FORMAT"),
       "format of IN (default: by extension and shape: .json = facetool, 3 lines of 9 = "
       "sfsnet, 9 lines of 3 = rgb-table, 9 numbers = dpr; other layouts of 27 numbers are "
       "ambiguous and need --from)");
  add_output_option(options, hidden, &output, "OUT", "light file to write (or give it after IN)");
  hidden.add_options()("input", po::value(&input)->required(), "light to read");
  po::positional_options_description positional;
  positional.add("input", 1).add("output", 1);
  po::variables_map values;
  if (!parse_command_options(
          "light convert IN (OUT | -o OUT) --to {facetool,sfsnet,dpr,rgb-table} [--from FORMAT]",
          "Converts a light between facetool's JSON (radiance coefficients in facetool's frame),\n"
          "SfSNet's 27-value text and DPR's 9-value grey text (shading coefficients in their own\n"
          "order and frame; see docs/conventions.md). Writing DPR keeps Rec. 601 luma only.",
          options, positional, args, values, hidden))
    return 0;
  check_option_ranges(values, {});  // no numeric options (a new one must get a range)
  check_output_option(values, "light convert", "the light file to write: OUT or -o OUT");
  light::Format to_format = light::Format::Facetool, from_format = light::Format::Facetool;
  try {
    to_format = light::format_from_name(to);
    if (!from.empty()) from_format = light::format_from_name(from);
  } catch (const Error& e) {
    throw UsageError(std::string("--to/--from: ") + e.what());
  }
  require_existing_file(input, "light file");
  if (from.empty()) from_format = light::guess_format(input);
  light::LightFile file = light::read_light(input, &from_format);
  if (from_format != light::Format::Facetool) {
    file.metadata["source"] = input;
    file.metadata["source_format"] = light::format_name(from_format);
  }
  light::write_light(output, file, to_format);
  std::cout << "light: " << output << " (" << light::format_name(to_format) << ", from "
            << light::format_name(from_format) << " '" << input << "')\n";
  if (to_format == light::Format::Dpr && from_format != light::Format::Dpr)
    std::cerr << "facetool: note: DPR lights are grey; the colour was reduced to Rec. 601 luma\n";
  return 0;
}

int run_show(const std::vector<std::string>& args) {
  po::options_description options("Options");
  po::options_description hidden;
  std::string input, output;
  int size = 256;
  add_output_option(options, hidden, &output, "FILE.png", "PNG to write");
  options.add_options()
      ("size", po::value(&size)->value_name("N")->default_value(256),
       "picture height in pixels (16..4096); the width is 3 N");
  hidden.add_options()("input", po::value(&input)->required(), "light file");
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map values;
  if (!parse_command_options(
          "light show LIGHT -o FILE.png [--size N]",
          "Draws a light (any format) so a person can see its direction and colour: on the left\n"
          "the hemisphere facing the camera (+Y up, +X right) as facetool renders it with albedo\n"
          "1 and no occlusion; on the right the radiance L(w) as an equirectangular panorama\n"
          "(centre = straight ahead of the camera (-Z), u = 1/4 is -X, 3/4 is +X, the edges are\n"
          "behind the camera; dotted lines mark the horizon and those three columns). Each panel\n"
          "is scaled by its own maximum; blue diagonal hatching marks negative values, which SH\n"
          "lights can have (use `light from-envmap --clamp` to remove them).",
          options, positional, args, values, hidden))
    return 0;
  check_option_ranges(values, {{"size", 16, 4096}});
  check_output_option(values, "light show", "the picture to write with -o FILE.png");
  const std::string extension = std::filesystem::path(output).extension().string();
  if (extension != ".png" && extension != ".PNG")
    throw UsageError("-o '" + output + "': light show writes a PNG; name it FILE.png");
  if (size < 16 || size > 4096) throw UsageError("--size must be within 16..4096");
  require_existing_file(input, "light file");
  const light::LightFile file = light::read_light(input);
  const light::LightPreview preview = light::write_light_preview(output, file.light, size);
  std::printf("preview: %s (%dx%d)\n  sphere shading max %.4g%s\n  radiance max %.4g, min %.4g%s\n",
              output.c_str(), preview.image.width, preview.image.height, preview.shading_max,
              preview.negative_shading ? " (negative somewhere: hatched blue)" : "",
              preview.radiance_max, preview.radiance_min,
              preview.radiance_min < 0 ? " (negative where hatched blue)" : "");
  return 0;
}

int run_light(CommandContext&, const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    (args.empty() ? std::cerr : std::cout) << kOverview;
    if (args.empty()) throw UsageError("light: no subcommand given");
    return 0;
  }
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (args[0] == "from-envmap") return run_from_envmap(rest);
  if (args[0] == "from-direction") return run_from_direction(rest);
  if (args[0] == "convert") return run_convert(rest);
  if (args[0] == "show") return run_show(rest);
  throw UsageError("unknown light subcommand '" + args[0] +
                   "'; subcommands: from-envmap, from-direction, convert, show");
}

const CommandRegistration registration{
    {"light", "SH lights: project environment maps, convert formats, draw a preview",
     run_light}};

}  // namespace
}  // namespace facetool
