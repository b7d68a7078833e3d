// `facetool render`: image and shading from albedo, normal, visibility, mask and light files.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/component_images.h"
#include "apps/facetool/commands/output_option.h"
#include "core/backend/registry.h"
#include "core/util/atomic_file.h"
#include "libs/io/exr_io.h"
#include "libs/io/image_io.h"
#include "libs/light/light_formats.h"
#include "core/plugin/renderer_plugin.h"
#include "core/sh/sh_basis.h"
#include "core/util/math_constants.h"
#include "core/util/file_checks.h"

namespace po = boost::program_options;

namespace facetool {
namespace {


struct OutputPaths {
  std::string image, shading;
  bool exr = false;
};

// OUT.png / OUT.exr and its sibling OUT_shading.<ext>; no extension means PNG.
OutputPaths output_paths(const std::string& output) {
  std::filesystem::path path(output);
  if (output.empty() || !path.has_filename())
    throw UsageError("-o '" + output + "' names a folder; give a file name such as OUT.png");
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension.empty()) path += ".png", extension = ".png";
  if (extension != ".png" && extension != ".exr")
    throw UsageError("-o '" + output + "': name the output .png (8-bit sRGB) or .exr (float)");
  if (path.filename().string() == path.extension().string())
    throw UsageError("-o '" + output + "' has no file name before the extension");
  OutputPaths paths;
  paths.exr = extension == ".exr";
  paths.image = path.string();
  paths.shading = (path.parent_path() / (path.stem().string() + "_shading" +
                                         path.extension().string())).string();
  const std::filesystem::path folder = path.parent_path().empty() ? "." : path.parent_path();
  std::error_code ec;
  check(std::filesystem::is_directory(folder, ec), "-o '", output, "': the folder '",
        folder.string(), "' does not exist; create it first");
  return paths;
}

// The default visibility, the same as synth's for pixels without a ray-cast label: every
// direction of the hemisphere above the surface open, v(w) = [w . n > 0]. Its SH coefficients
// follow from the Funk-Hecke theorem, v_i = lambda_l Y_i(n) with lambda_l = 2 pi int_0^1 P_l:
// 2 pi, pi and 0 for bands 0, 1, 2 (so v_0 = sqrt(pi)). Zero-length normals get v = 0.
ComponentImage open_hemisphere_visibility(const ComponentImage& normal) {
  constexpr double kBandFactor[3] = {2 * kPi, kPi, 0.0};
  ComponentImage visibility;
  visibility.width = normal.width;
  visibility.height = normal.height;
  visibility.channels = 9;
  const size_t pixels = normal.plane_size();
  visibility.planes.assign(9 * pixels, 0.0f);
  for (size_t p = 0; p < pixels; ++p) {
    const double x = normal.plane(0)[p], y = normal.plane(1)[p], z = normal.plane(2)[p];
    const double length = std::sqrt(x * x + y * y + z * z);
    if (!(length > 0.0) || !std::isfinite(length)) continue;
    double basis[sh::kCoeffCount];
    sh::sh_basis(x / length, y / length, z / length, basis);
    for (int i = 0; i < sh::kCoeffCount; ++i)
      visibility.plane(i)[p] = static_cast<float>(kBandFactor[sh::sh_band(i)] * basis[i]);
  }
  return visibility;
}

void check_same_size(const ComponentImage& image, const ComponentImage& reference) {
  check(image.width == reference.width && image.height == reference.height, image.option, " '",
        image.path, "' is ", image.width, "x", image.height, " but ", reference.option, " '",
        reference.path, "' is ", reference.width, "x", reference.height,
        "; all component images must have the same size");
}

// A [3,H,W] planar result encoded as the PNG or EXR file `path`.
FileContents encode_result(const std::string& path, const std::vector<float>& planes, int width,
                           int height, bool exr, const std::string& description) {
  if (exr) {
    LayeredImage image(width, height, {"R", "G", "B"});
    std::copy(planes.begin(), planes.end(), image.pixels.begin());
    image.set_metadata("facetool:content", description);
    return {path, encode_exr(path, image)};
  } else {
    return {path, encode_png(path, rgb_from_planar(planes.data(), width, height))};
  }
}

int run_render(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string albedo_path, normal_path, visibility_path, mask_path, light_path, output;
  std::string light_format, renderer_name = "sh_renderer";
  options.add_options()
      ("albedo", po::value(&albedo_path)->value_name("FILE")->required(),
       "albedo: RGB in [0, 1]; EXR linear, PNG sRGB-encoded")
      ("normal", po::value(&normal_path)->value_name("FILE")->required(),
       "world-frame normals: EXR float XYZ, or PNG holding (n + 1) / 2 per channel")
      ("visibility", po::value(&visibility_path)->value_name("FILE.exr"),
       "9-channel EXR of SH visibility coefficients (default: the open hemisphere above "
       "the surface, as synth uses where it casts no rays; docs/conventions.md)")
      ("mask", po::value(&mask_path)->value_name("FILE"),
       "grey image; pixels > 0.5 are rendered, others are 0 (default: every pixel)")
      ("light", po::value(&light_path)->value_name("FILE")->required(),
       "light file: facetool .json, SfSNet (3 lines of 9), DPR (9 numbers) or rgb-table (9 "
       "lines of R G B); text layouts are told apart by their shape")
      ("light-format", po::value(&light_format)->value_name("FORMAT"),
       "format of --light when guessing is not wanted: facetool, sfsnet, dpr or rgb-table")
      ("renderer", po::value(&renderer_name)->value_name("NAME")->default_value("sh_renderer"),
       "renderer plugin to use");
  po::options_description hidden;
  add_output_option(options, hidden, &output, "OUT.{png,exr}",
                    "image to write; the shading goes to OUT_shading.<ext> beside it");
  po::variables_map values;
  if (!parse_command_options(
          "render --albedo A --normal N [--visibility V] [--mask M] --light L -o OUT [options]",
          "Renders image = albedo * shading, shading = 1/pi sum_i L_i sum_jk v_j c_k(n) T_ijk\n"
          "(paper eq. 1; docs/conventions.md) with the renderer plugin on the chosen --backend.\n"
          "Multi-layer EXRs such as synth samples work too: their albedo.*, normal.*,\n"
          "visibility.* and mask channels are used. All images must have the same size.\n"
          "Writes OUT and OUT_shading.<ext>: PNG (8-bit sRGB, values clipped to [0, 1]) or EXR\n"
          "(linear float) by OUT's extension. Nothing is written if anything fails.",
          options, po::positional_options_description(), args, values, hidden))
    return 0;
  check_option_ranges(values, {});  // no numeric options (a new one must get a range)
  check_output_option(values, "render", "the image to write with -o OUT.png or -o OUT.exr");
  const OutputPaths paths = output_paths(output);
  light::Format format = light::Format::Facetool;
  if (!light_format.empty()) {
    try {
      format = light::format_from_name(light_format);
    } catch (const Error& e) {
      throw UsageError(std::string("--light-format: ") + e.what());
    }
  }

  // Read and check everything before any work.
  check_regular_input_file(light_path, kMaxTextFileBytes, "--light");
  // Neither output may be one of the inputs: it would be replaced by the rendering.
  std::vector<std::string> input_files = {albedo_path, normal_path, light_path};
  if (!visibility_path.empty()) input_files.push_back(visibility_path);
  if (!mask_path.empty()) input_files.push_back(mask_path);
  check_output_is_not_an_input(paths.image, "-o", input_files);
  check_output_is_not_an_input(paths.shading, "-o (its _shading sibling)", input_files);
  const light::LightFile light =
      light::read_light(light_path, light_format.empty() ? nullptr : &format);
  ComponentImage albedo = read_albedo_image(albedo_path);
  ComponentImage normal = read_normal_image(normal_path);
  check_same_size(normal, albedo);
  const int width = albedo.width, height = albedo.height;
  const size_t pixels = albedo.plane_size();
  std::vector<char> rendered;
  ComponentImage mask;
  if (!mask_path.empty()) {
    mask = read_mask_image(mask_path);
    check_same_size(mask, albedo);
    check_finite(mask, {});
    rendered.resize(pixels);
    for (size_t p = 0; p < pixels; ++p) rendered[p] = mask.plane(0)[p] > 0.5f;
  }
  ComponentImage visibility;
  if (!visibility_path.empty()) {
    visibility = read_visibility_image(visibility_path);
    check_same_size(visibility, albedo);
  } else {
    visibility = open_hemisphere_visibility(normal);
  }
  check_finite(albedo, rendered);
  check_finite(normal, rendered);
  if (!visibility_path.empty()) check_finite(visibility, rendered);

  Backend& backend = get_backend(context.backend);
  PluginLoader& loader = context.plugins();
  const std::shared_ptr<Plugin> object =
      loader.create(loader.find(FACETOOL_PLUGIN_RENDERER, renderer_name));
  auto* renderer = dynamic_cast<RendererPlugin*>(object.get());
  check(renderer != nullptr, "plugin '", renderer_name,
        "' does not implement the renderer interface");

  const int64_t h = height, w = width;
  RenderInputs inputs;
  inputs.albedo = Tensor::from_host(backend, Shape{1, 3, h, w}, albedo.planes);
  inputs.normal = Tensor::from_host(backend, Shape{1, 3, h, w}, normal.planes);
  inputs.visibility = Tensor::from_host(backend, Shape{1, 9, h, w}, visibility.planes);
  inputs.light = Tensor::from_host(backend, Shape{1, 27},
                                   std::vector<float>(light.light.begin(), light.light.end()));
  if (!mask_path.empty()) inputs.mask = Tensor::from_host(backend, Shape{1, 1, h, w}, mask.planes);
  RenderOutputs outputs;
  renderer->forward(inputs, outputs);
  const std::vector<float> image = outputs.image.to_host();
  const std::vector<float> shading = outputs.shading.to_host();

  // Both files appear only once both are complete; on failure neither is touched.
  write_files_atomically(
      {encode_result(paths.image, image, width, height, paths.exr,
                     "image = albedo * shading, linear RGB, rendered by " + renderer_name),
       encode_result(paths.shading, shading, width, height, paths.exr,
                     "shading, linear RGB, rendered by " + renderer_name)});

  const size_t count = rendered.empty() ? pixels : std::count(rendered.begin(), rendered.end(), 1);
  float shading_max = 0.0f;
  for (float v : shading) shading_max = std::max(shading_max, v);
  std::printf("image: %s\nshading: %s\n  %dx%d, %zu pixels rendered by %s on %s; "
              "shading max %.4g%s\n",
              paths.image.c_str(), paths.shading.c_str(), width, height, count,
              renderer_name.c_str(), context.backend.c_str(), shading_max,
              !paths.exr && shading_max > 1.0f ? " (clipped to 1 in the PNG; use .exr to keep it)"
                                               : "");
  return 0;
}

const CommandRegistration registration{
    {"render", "render image and shading from albedo, normal, visibility, mask and light files",
     run_render}};

}  // namespace
}  // namespace facetool
