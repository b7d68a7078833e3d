// `facetool synth`: generates synthetic training samples (paper section 4.1) as EXR files.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/output_option.h"
#include "core/backend/registry.h"
#include "core/plugin/renderer_plugin.h"
#include "libs/synth/plugin_renderer.h"
#include "libs/synth/random.h"
#include "libs/synth/synth_runner.h"
#include "core/util/shard.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

// "128" -> 128x128, "160x128" -> width 160, height 128.
void parse_size(const std::string& text, int& width, int& height) {
  try {
    size_t used = 0;
    const size_t x = text.find('x');
    width = std::stoi(text.substr(0, x), &used);
    height = x == std::string::npos ? width : std::stoi(text.substr(x + 1));
  } catch (const std::exception&) {
    width = height = 0;
  }
  if (width <= 0 || height <= 0 || width > 4096 || height > 4096)
    throw UsageError("--size '" + text + "' is not N or WxH with 1..4096 pixels");
}

int run_synth_command(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string face_model, mesh, backgrounds, out, shard = "0/1", size = "128", contact_sheet;
  std::vector<std::string> lights;
  int64_t count = 1;
  uint64_t seed = 0;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  int contact_rows = 16;
  std::string renderer_name = "sh_renderer";
  SynthSettings settings;
  options.add_options()
      ("face-model", po::value(&face_model)->value_name("DIR"),
       "ICT Face Model folder (generic_neutral_mesh.obj, identityNNN.obj, expression .obj)")
      ("mesh", po::value(&mesh)->value_name("FILE.obj"),
       "render this mesh (e.g. a face scan) instead of random ICT faces")
      ("lights", po::value(&lights)->value_name("DIR")->composing(),
       "folder (or file) of .hdr/.exr environment maps and .txt SH lights; repeatable "
       "(default: Debian blender-data's studio lights when installed)")
      ("backgrounds", po::value(&backgrounds)->value_name("DIR"),
       "images without faces for the background (default: views of the environment map)")
      ("count", po::value(&count)->value_name("N")->default_value(1), "samples in the whole run")
      ("seed", po::value(&seed)->value_name("S")->default_value(0), "run seed")
      ("shard", po::value(&shard)->value_name("i/n")->default_value("0/1"),
       "make only samples with index % n == i")
      ("threads", po::value(&threads)->value_name("T")->default_value(threads),
       "worker threads (output does not depend on it)")
      ("size", po::value(&size)->value_name("N|WxH")->default_value("128"), "image size")
      ("framing", po::value<std::string>()->default_value("v1"),
       "how the face is framed: v1, v2, or 'zoom Z centre X Y border edge-repeat|ring-mean' "
       "(the same as the model's and prepare-real's; docs/synthetic-data.md, \"Framing\")")
      ("photo-edges", po::value(&settings.photo_edges.fraction)->default_value(0.0),
       "fraction of the samples crossed by a simulated photo edge, filled beyond it as "
       "alignment fills crops beyond a real photo (needs the ring-mean border fill)")
      ("albedo-textures", po::value<std::string>()->value_name("DIR"),
       "paint photo albedo textures (`facetool unwrap`'s) on the faces instead of the procedural skin, "
       "lips and brows, each coloured to the sample's skin tone (docs/synthetic-data.md); needs --face-model")
      ("albedo-texture-fraction", po::value(&settings.albedo_texture_fraction)->default_value(1.0),
       "with --albedo-textures: the fraction of the samples painted (the rest procedural)")
      ("directions", po::value(&settings.direction_count)->default_value(872),
       "visibility directions per pixel")
      ("identity-truncation", po::value(&settings.shape.identity_truncation)->default_value(2.5),
       "identity weights ~ N(0,1) limited to +-this")
      ("max-expressions", po::value(&settings.shape.max_active_expressions)->default_value(4),
       "at most this many active expressions per face")
      ("expression", po::value<std::vector<std::string>>()->value_name("NAME=W")->composing(),
       "set this ICT expression to weight W in every face, after the random ones (repeatable; "
       "e.g. --expression eyeBlink_L=1 --expression eyeBlink_R=1 for closed eyes)")
      ("contact-sheet", po::value(&contact_sheet)->value_name("FILE.png"),
       "write a PNG: per sample image, albedo, normal, shading, ambient visibility")
      ("contact-sheet-rows", po::value(&contact_rows)->default_value(16), "samples on the sheet")
      ("overwrite", po::bool_switch(),
       "regenerate samples already in --out that were made with other settings (lights, "
       "faces, size, seed, ...) instead of stopping; damaged samples are always regenerated")
      ("renderer", po::value(&renderer_name)->default_value("sh_renderer"),
       "renderer plugin that makes the images (the network's rendering layer), or 'reference' "
       "for the SH library's double-precision triple product");
  po::options_description hidden;
  add_output_option(options, hidden, &out, "DIR", "output folder");
  po::variables_map values;
  if (!parse_command_options(
          "synth -o DIR (--face-model DIR | --mesh FILE.obj) [options]",
          "Generates synthetic training samples as in the paper's section 4.1: random ICT faces\n"
          "with procedural albedo, posed and lit by SH lights from environment maps; per-pixel\n"
          "visibility from Embree ray casting. One EXR per sample (image, albedo, normal, mask,\n"
          "9 visibility coefficients, depth; light/pose/seed as metadata) and a manifest.\n"
          "Interrupted runs resume; the same seed gives the same samples for any --threads.\n"
          "Rays are cast in the hemisphere above the surface only; pixels without ray-cast\n"
          "visibility are rendered with that open hemisphere, which is also what render assumes\n"
          "without --visibility (docs/conventions.md).",
          options, po::positional_options_description(), args, values, hidden))
    return 0;
  check_option_ranges(values, {{"count", 0, 1e7},
                               {"seed", 0, 18446744073709551615.0},
                               {"threads", 1, 1024},
                               {"directions", 1, 100000},
                               {"identity-truncation", Random::kMinTruncation, 100},
                               {"max-expressions", 0, 1000},
                               {"contact-sheet-rows", 1, 10000},
                               {"photo-edges", 0, 1},
                               {"albedo-texture-fraction", 0, 1}});
  check_output_option(values, "synth", "an output folder with -o DIR");
  if (face_model.empty() == mesh.empty())
    throw UsageError(face_model.empty()
                         ? std::string("give --face-model DIR or --mesh FILE.obj: ") + kIctFaceKitHint
                         : "give either --face-model or --mesh, not both");
  parse_size(size, settings.camera.width, settings.camera.height);
  settings.camera.framing = parse_framing(values["framing"].as<std::string>(), "synth: --framing");
  if (settings.photo_edges.fraction > 0 && settings.camera.framing.border != BorderFill::kRingMean)
    throw UsageError("synth: --photo-edges needs a --framing with the ring-mean border fill (e.g. v2)");
  SynthRunOptions run;
  parse_shard(shard, run.shard_index, run.shard_count);
  run.output_dir = out;
  run.count = count;
  run.seed = seed;
  run.threads = threads;
  run.contact_sheet = contact_sheet;
  run.contact_sheet_rows = contact_rows;
  run.overwrite = values["overwrite"].as<bool>();
  if (values.count("expression"))
    for (const std::string& item : values["expression"].as<std::vector<std::string>>()) {
      const size_t eq = item.find('=');
      double weight = 0;
      try {
        size_t used = 0;
        if (eq != std::string::npos) weight = std::stod(item.substr(eq + 1), &used);
        if (eq == std::string::npos || eq == 0 || used != item.size() - eq - 1) throw std::invalid_argument(item);
      } catch (const std::exception&) {
        throw UsageError("synth: --expression '" + item + "' is not NAME=WEIGHT (e.g. eyeBlink_L=1)");
      }
      if (!(weight >= -2 && weight <= 2))
        throw UsageError("synth: --expression '" + item + "': the weight must be in [-2, 2]");
      settings.shape.fixed_expressions.emplace_back(item.substr(0, eq), weight);
    }
  if (count < 0) throw UsageError("--count must not be negative");
  if (threads <= 0) throw UsageError("--threads must be positive");
  if (lights.empty()) {
    check(std::filesystem::is_directory(kBlenderStudioLightsDir),
          "no --lights given and Debian's blender-data lights (", kBlenderStudioLightsDir,
          ") are not installed: pass --lights DIR with .hdr/.exr environment maps or .txt SH "
          "lights, or install blender-data");
    lights.push_back(kBlenderStudioLightsDir);
  }

  if (values.count("albedo-textures")) {
    if (face_model.empty()) throw UsageError("synth: --albedo-textures needs --face-model (textures live on the ICT face)");
    settings.albedo_textures = std::make_shared<const std::vector<AlbedoTexture>>(
        read_albedo_textures(values["albedo-textures"].as<std::string>()));
  } else if (!values["albedo-texture-fraction"].defaulted()) {
    throw UsageError("synth: --albedo-texture-fraction is for --albedo-textures");
  }
  FaceSource faces;
  if (!face_model.empty())
    faces.model = std::make_shared<const FaceModel>(FaceModel::load(face_model));
  else
    faces.mesh = std::make_shared<const FaceMesh>(load_user_mesh(mesh));
  std::shared_ptr<const ComponentRenderer> renderer;
  if (renderer_name == "reference") {
    renderer = make_reference_renderer();
  } else {
    auto plugin = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, renderer_name);
    renderer = make_plugin_renderer(plugin, get_backend(context.backend));
  }
  SampleGenerator generator(faces, load_light_sources(lights), BackgroundSource(backgrounds),
                            renderer, settings);
  if (context.verbose)
    std::cerr << "synth: " << generator.lights().size() << " light sources, renderer "
              << renderer->name() << "\n";

  ProgressBar bar("synth", (count - run.shard_index + run.shard_count - 1) / run.shard_count,
                  "samples");
  run.progress = [&bar](int64_t done, int64_t) { bar.update(done); };
  const SynthRunReport report = run_synth(generator, run);
  bar.finish();
  const double rate = report.seconds > 0 ? report.generated / report.seconds : 0.0;
  const double mrays = report.seconds > 0 ? report.rays_cast / report.seconds / 1e6 : 0.0;
  const double cpu_per_sample = report.generated > 0 ? report.cpu_seconds / report.generated : 0.0;
  if (report.repaired > 0)
    std::printf("%lld damaged samples regenerated\n", static_cast<long long>(report.repaired));
  std::printf("%lld generated, %lld already present, in %.1f s: %.2f samples/s, %.1f Mrays/s "
              "(%d threads; %.3f CPU s per sample)\nmanifest: %s\n",
              static_cast<long long>(report.generated), static_cast<long long>(report.reused),
              report.seconds, rate, mrays, threads, cpu_per_sample, report.manifest_path.c_str());
  if (!contact_sheet.empty()) std::printf("contact sheet: %s\n", contact_sheet.c_str());
  return 0;
}

const CommandRegistration registration{
    {"synth", "generate synthetic training samples (faces, lights, visibility) as EXR files",
     run_synth_command}};

}  // namespace
}  // namespace facetool
