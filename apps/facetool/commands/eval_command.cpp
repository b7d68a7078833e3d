// `facetool eval`: a trained network on samples with or without ground truth: the paper's
// Table 1 (normal angular error), component errors, reconstruction PSNR/SSIM in the mask.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/trained_model.h"
#include "core/backend/registry.h"
#include "core/data/training_sample.h"
#include "core/inference/decomposer.h"
#include "core/io/atomic_file.h"
#include "core/io/image_io.h"
#include "core/plugin/renderer_plugin.h"
#include "core/synth/gbuffer.h"
#include "core/train/eval_metrics.h"
#include "core/util/progress_bar.h"

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace facetool {
namespace {

struct ImageResult {
  std::string file;
  bool truth = false;
  double normal_mean = NAN, albedo_mse = NAN, visibility_mse = NAN, light = NAN;
  double psnr = NAN, ssim = NAN;
};

std::string number(double v) {
  if (std::isnan(v)) return "";
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

double mean_of(const std::vector<ImageResult>& rs, double ImageResult::*field) {
  double sum = 0;
  int n = 0;
  for (const ImageResult& r : rs)
    if (std::isfinite(r.*field)) sum += r.*field, ++n;
  return n ? sum / n : NAN;
}

// One contact-sheet row: input, reconstruction, predicted normal, true normal (grey if none).
void add_sheet_row(RgbImage& sheet, int row, int size, const float* input, const float* recon,
                   const float* normal, const float* truth) {
  const size_t plane = static_cast<size_t>(size) * size;
  const float* tiles[4] = {input, recon, normal, truth};
  for (int t = 0; t < 4; ++t)
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        float* px = sheet.at(t * (size + 2) + x, row * (size + 2) + y);
        for (int c = 0; c < 3; ++c) {
          const size_t i = c * plane + static_cast<size_t>(y) * size + x;
          if (!tiles[t]) px[c] = 0.2f;
          else if (t >= 2) px[c] = srgb_to_linear(std::clamp(0.5f * (tiles[t][i] + 1.0f), 0.0f, 1.0f));
          else px[c] = std::clamp(tiles[t][i], 0.0f, 1.0f);
        }
      }
}

int run_eval(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string model, data, out_dir;
  int batch = 8;
  options.add_options()
      ("model", po::value(&model)->value_name("WEIGHTS")->required(), "trained weights")
      ("data", po::value(&data)->value_name("DIR")->required(),
       "folder of sample_*.exr (synthetic: with ground truth; real: reconstruction only)")
      ("output,o", po::value(&out_dir)->value_name("DIR")->required(),
       "writes per_image.csv, summary.json, summary.md")
      ("batch", po::value(&batch)->default_value(8), "images per network run")
      ("contact-sheet", "also write contact_sheet.png: input, reconstruction, normal, true normal");
  po::variables_map values;
  if (!parse_command_options(
          "eval --model WEIGHTS --data DIR -o OUT [--contact-sheet]",
          "Evaluates a trained network. On synthetic samples (ground truth): the paper's Table 1 "
          "(normal angular\nerror mean +- std, % of pixels under 20, 25, 30 degrees), albedo and "
          "visibility MSE, light error E_L,\nand reconstruction PSNR and SSIM; on real samples "
          "(facetool-real-1, pseudo labels are not truth)\nPSNR and SSIM only. Everything is "
          "measured in the face mask eroded by one pixel.",
          options, {}, args, values))
    return 0;
  check_option_ranges(values, {{"batch", 1, 1024}});
  if (batch < 1) throw UsageError("eval: --batch must be at least 1");
  check(fs::is_directory(data), "eval: data folder '", data, "' does not exist");
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(data)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.rfind("sample_", 0) == 0 && e.path().extension() == ".exr")
      files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  check(!files.empty(), "eval: '", data, "' holds no sample_*.exr files");

  Backend& backend = get_backend(context.backend);
  auto network = load_trained_network(context, backend, model);
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, "sh_renderer");
  Decomposer decomposer(*network, *renderer);
  const int size = network->config().input_size;
  const size_t plane = static_cast<size_t>(size) * size;
  fs::create_directories(out_dir);

  std::vector<ImageResult> results;
  std::vector<double> angles;
  RgbImage sheet;
  const bool want_sheet = values.count("contact-sheet") != 0;
  if (want_sheet) {
    sheet.width = 4 * (size + 2);
    sheet.height = static_cast<int>(files.size()) * (size + 2);
    sheet.pixels.assign(static_cast<size_t>(sheet.width) * sheet.height * 3, 1.0f);
  }
  ProgressBar progress("eval", static_cast<int64_t>(files.size()), "images");
  for (size_t first = 0; first < files.size(); first += batch) {
    const int count = static_cast<int>(std::min(files.size() - first, static_cast<size_t>(batch)));
    std::vector<TrainingSample> samples;
    std::vector<float> planes;
    for (int i = 0; i < count; ++i) {
      samples.push_back(read_training_sample(files[first + i], false));
      const TrainingSample& s = samples.back();
      check(s.width == size && s.height == size, "sample '", files[first + i], "' is ", s.width,
            "x", s.height, " but the network takes ", size, "x", size);
      planes.insert(planes.end(), s.image.begin(), s.image.end());
    }
    const Decomposition d = decomposer.run(backend, planes, count);
    for (int i = 0; i < count; ++i) {
      const TrainingSample& s = samples[i];
      const std::vector<float> mask = erode_mask(s.mask, s.width, s.height);
      ImageResult r;
      r.file = fs::path(files[first + i]).filename().string();
      r.truth = !s.real;
      const float* recon = d.reconstruction.data() + i * 3 * plane;
      const float* normal = d.normal.data() + i * 3 * plane;
      r.psnr = masked_psnr(recon, s.image.data(), mask.data(), size, size);
      r.ssim = masked_ssim(recon, s.image.data(), mask.data(), size, size);
      if (r.truth) {
        std::vector<double> own;
        normal_angles_deg(normal, s.normal.data(), mask.data(), plane, own);
        r.normal_mean = summarize_angles(own).mean;
        angles.insert(angles.end(), own.begin(), own.end());
        r.albedo_mse = masked_mse(d.albedo.data() + i * 3 * plane, s.albedo.data(), mask.data(), 3, plane);
        r.visibility_mse =
            masked_mse(d.visibility.data() + i * 9 * plane, s.visibility.data(), mask.data(), 9, plane);
        r.light = light_error(d.light.data() + i * 27, s.light.data());
      }
      if (want_sheet)
        add_sheet_row(sheet, static_cast<int>(first + i), size, s.image.data(), recon, normal,
                      r.truth ? s.normal.data() : nullptr);
      results.push_back(r);
    }
    progress.advance(count);
  }
  progress.finish();

  std::ostringstream csv;
  csv << "file,ground_truth,normal_error_mean_deg,albedo_mse,visibility_mse,light_error,psnr_db,ssim\n";
  for (const ImageResult& r : results)
    csv << r.file << "," << (r.truth ? 1 : 0) << "," << number(r.normal_mean) << ","
        << number(r.albedo_mse) << "," << number(r.visibility_mse) << "," << number(r.light)
        << "," << number(r.psnr) << "," << number(r.ssim) << "\n";
  const std::string csv_text = csv.str();
  write_file_atomically((fs::path(out_dir) / "per_image.csv").string(), csv_text.data(), csv_text.size());

  const AngularSummary a = summarize_angles(angles);
  auto json_number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json summary = {
      {"model", model}, {"data", data}, {"images", results.size()},
      {"images_with_ground_truth", std::count_if(results.begin(), results.end(), [](const ImageResult& r) { return r.truth; })},
      {"psnr_db_mean", json_number(mean_of(results, &ImageResult::psnr))},
      {"ssim_mean", json_number(mean_of(results, &ImageResult::ssim))}};
  if (a.pixels > 0) {
    summary["normal_error"] = {{"mean_deg", a.mean}, {"std_deg", a.std}, {"under_20_percent", a.under20},
                               {"under_25_percent", a.under25}, {"under_30_percent", a.under30},
                               {"pixels", a.pixels}};
    summary["albedo_mse_mean"] = json_number(mean_of(results, &ImageResult::albedo_mse));
    summary["visibility_mse_mean"] = json_number(mean_of(results, &ImageResult::visibility_mse));
    summary["light_error_mean"] = json_number(mean_of(results, &ImageResult::light));
  }
  const std::string json_text = summary.dump(2) + "\n";
  write_file_atomically((fs::path(out_dir) / "summary.json").string(), json_text.data(), json_text.size());

  std::ostringstream md;
  md.setf(std::ios::fixed);
  md.precision(2);
  if (a.pixels > 0) {
    md << "| method | mean +- std (deg) | < 20 deg | < 25 deg | < 30 deg |\n| --- | --- | --- | --- | --- |\n"
       << "| facetool (" << fs::path(model).filename().string() << ") | " << a.mean << " +- " << a.std
       << " | " << a.under20 << "% | " << a.under25 << "% | " << a.under30 << "% |\n\n";
  }
  md << "| images | albedo MSE | visibility MSE | light E_L | PSNR (dB) | SSIM |\n| --- | --- | --- | --- | --- | --- |\n"
     << "| " << results.size() << " | " << number(mean_of(results, &ImageResult::albedo_mse)) << " | "
     << number(mean_of(results, &ImageResult::visibility_mse)) << " | "
     << number(mean_of(results, &ImageResult::light)) << " | "
     << number(mean_of(results, &ImageResult::psnr)) << " | "
     << number(mean_of(results, &ImageResult::ssim)) << " |\n";
  const std::string md_text = md.str();
  write_file_atomically((fs::path(out_dir) / "summary.md").string(), md_text.data(), md_text.size());
  if (want_sheet) write_png_atomically((fs::path(out_dir) / "contact_sheet.png").string(), sheet);
  std::cout << md_text;
  return 0;
}

const CommandRegistration registration{
    {"eval", "evaluate a trained network: normal error (Table 1), PSNR/SSIM, per-image CSV",
     run_eval}};

}  // namespace
}  // namespace facetool
