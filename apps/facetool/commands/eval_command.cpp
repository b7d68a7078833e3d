// `facetool eval`: a trained network on samples with or without ground truth: the paper's
// Table 1 (normal angular error), component errors, reconstruction PSNR/SSIM in the mask.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "apps/facetool/commands/trained_model.h"
#include "apps/facetool/infer/network_loading.h"
#include "libs/model/default_model.h"
#include "core/backend/registry.h"
#include "libs/data/training_sample.h"
#include "libs/inference/batched_decomposition.h"
#include "libs/inference/decomposer.h"
#include "core/util/atomic_file.h"
#include "libs/image/gaussian_blur.h"
#include "libs/io/image_io.h"
#include "core/plugin/renderer_plugin.h"
#include "libs/synth/gbuffer.h"
#include "core/util/shard.h"
#include "libs/train/eval_metrics.h"
#include "core/util/file_checks.h"
#include "core/util/folder_lock.h"
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
  double blurred_psnr = NAN;  // of the input blurred by --blur-sigma: the baseline for psnr
  // The normal angles' sufficient statistics, so shards' results merge into the summary.
  int64_t pixels = 0, under20 = 0, under25 = 0, under30 = 0;
  double angle_sum = 0, angle_sum_sq = 0;
};

// The largest per_image.csv or summary.json --merge reads (about a million images).
constexpr uint64_t kMaxCsvBytes = uint64_t{1} << 30;

constexpr const char* kCsvHeader =
    "file,ground_truth,normal_error_mean_deg,albedo_mse,visibility_mse,light_error,psnr_db,ssim,"
    "normal_pixels,normal_angle_sum_deg,normal_angle_sum_sq_deg,under_20_pixels,under_25_pixels,"
    "under_30_pixels,blurred_psnr_db";

std::string number(double v) {
  if (std::isnan(v)) return "";
  std::ostringstream s;
  s.precision(17);  // exact round trip: merged shards give the unsharded summary
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

// per_image.csv, summary.json and summary.md of `results` (one run, or merged shards).
std::string write_outputs(const std::string& out_dir, const std::string& model,
                          const std::string& data, const std::vector<ImageResult>& results,
                          const AngularSummary& a, double blur_sigma, const std::string& shard = "") {
  std::ostringstream csv;
  csv << kCsvHeader << "\n";
  for (const ImageResult& r : results)
    csv << r.file << "," << (r.truth ? 1 : 0) << "," << number(r.normal_mean) << ","
        << number(r.albedo_mse) << "," << number(r.visibility_mse) << "," << number(r.light)
        << "," << number(r.psnr) << "," << number(r.ssim) << "," << r.pixels << ","
        << number(r.angle_sum) << "," << number(r.angle_sum_sq) << "," << r.under20 << ","
        << r.under25 << "," << r.under30 << "," << number(r.blurred_psnr) << "\n";
  const std::string csv_text = csv.str();
  write_file_atomically((fs::path(out_dir) / "per_image.csv").string(), csv_text.data(), csv_text.size());

  auto json_number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json summary = {
      {"model", model}, {"data", data}, {"images", results.size()},
      {"images_with_ground_truth", std::count_if(results.begin(), results.end(), [](const ImageResult& r) { return r.truth; })},
      {"psnr_db_mean", json_number(mean_of(results, &ImageResult::psnr))},
      {"ssim_mean", json_number(mean_of(results, &ImageResult::ssim))},
      {"blurred_psnr_db_mean", json_number(mean_of(results, &ImageResult::blurred_psnr))},
      {"blur_sigma_px", json_number(blur_sigma)}};
  if (a.pixels > 0) {
    summary["normal_error"] = {{"mean_deg", a.mean}, {"std_deg", a.std}, {"under_20_percent", a.under20},
                               {"under_25_percent", a.under25}, {"under_30_percent", a.under30},
                               {"pixels", a.pixels}};
    summary["albedo_mse_mean"] = json_number(mean_of(results, &ImageResult::albedo_mse));
    summary["visibility_mse_mean"] = json_number(mean_of(results, &ImageResult::visibility_mse));
    summary["light_error_mean"] = json_number(mean_of(results, &ImageResult::light));
  }
  if (!shard.empty()) summary["shard"] = shard;  // --merge checks that no shard is missing
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
  md << "| images | albedo MSE | visibility MSE | light E_L | PSNR (dB) | SSIM | blurred input's PSNR (dB, sigma "
     << number(blur_sigma) << " px) |\n| --- | --- | --- | --- | --- | --- | --- |\n"
     << "| " << results.size() << " | " << number(mean_of(results, &ImageResult::albedo_mse)) << " | "
     << number(mean_of(results, &ImageResult::visibility_mse)) << " | "
     << number(mean_of(results, &ImageResult::light)) << " | "
     << number(mean_of(results, &ImageResult::psnr)) << " | "
     << number(mean_of(results, &ImageResult::ssim)) << " | "
     << number(mean_of(results, &ImageResult::blurred_psnr)) << " |\n";
  const std::string md_text = md.str();
  write_file_atomically((fs::path(out_dir) / "summary.md").string(), md_text.data(), md_text.size());
  return md_text;
}

// Splits one CSV line at commas (the file names have none: sample_XXXXXXXX.exr).
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) out.push_back(field);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

double csv_number(const std::string& text) { return text.empty() ? NAN : std::stod(text); }

// Throws facetool::Error when `out_dir` holds the results of another shard of an eval (its
// summary.json names a shard other than `shard`, "" for an unsharded run): writing there would
// replace them. A rerun of the same shard replaces its own results.
void check_not_another_shards_folder(const std::string& out_dir, const std::string& shard) {
  const std::string summary_path = (fs::path(out_dir) / "summary.json").string();
  std::error_code ec;
  if (!fs::is_regular_file(summary_path, ec)) return;
  const nlohmann::json j =
      nlohmann::json::parse(read_regular_input_file(summary_path, kMaxCsvBytes, "eval: earlier summary"), nullptr, false);
  if (!j.is_object()) return;
  const std::string theirs = j.contains("shard") && j["shard"].is_string() ? j["shard"].get<std::string>() : "";
  if (theirs == shard) return;
  fail("eval: -o '", out_dir, "' holds the results of ", theirs.empty() ? std::string("an unsharded eval") : "shard " + theirs,
       "; writing ", shard.empty() ? std::string("an unsharded run's") : "shard " + shard + "'s",
       " there would replace them: give each shard its own folder (then eval --merge)");
}

// `facetool eval --merge`: the shards' per-image rows, in file order, and their summary.
int merge_shards(const std::vector<std::string>& shards, const std::string& out_dir) {
  std::vector<ImageResult> results;
  std::string model, data;
  double blur_sigma = NAN;
  // -o naming one of the shards would replace that shard's table with the merged one.
  for (const std::string& dir : shards)
    check(!fs::exists(out_dir) || !fs::equivalent(out_dir, dir), "eval --merge: -o '", out_dir,
          "' is the shard folder '", dir, "'; writing there would replace that shard's ",
          "results: choose another -o");
  int shard_count = 0, unlabelled_shards = 0;
  std::set<int> shards_seen;
  for (const std::string& dir : shards) {
    const std::string path = (fs::path(dir) / "per_image.csv").string();
    check_input_folder(dir, "eval --merge: shard folder");
    check(fs::exists(path), "eval --merge: '", path, "' does not exist; run eval --shard i/n -o ",
          dir, " first");
    std::istringstream in(read_regular_input_file(path, kMaxCsvBytes, "eval --merge: shard table"));
    std::string line;
    std::getline(in, line);
    check(line == kCsvHeader, "eval --merge: '", path, "' is not a per_image.csv of this facetool "
          "version (its header differs); rerun that shard");
    for (int row = 2; std::getline(in, line); ++row) {
      const std::vector<std::string> f = split_csv(line);
      check(f.size() == 15, "eval --merge: '", path, "' line ", row, " has ", f.size(),
            " fields, expected 15");
      ImageResult r;
      try {
        r.file = f[0];
        r.truth = f[1] == "1";
        r.normal_mean = csv_number(f[2]);
        r.albedo_mse = csv_number(f[3]);
        r.visibility_mse = csv_number(f[4]);
        r.light = csv_number(f[5]);
        r.psnr = csv_number(f[6]);
        r.ssim = csv_number(f[7]);
        r.pixels = std::stoll(f[8]);
        r.angle_sum = std::stod(f[9]);
        r.angle_sum_sq = std::stod(f[10]);
        r.under20 = std::stoll(f[11]);
        r.under25 = std::stoll(f[12]);
        r.under30 = std::stoll(f[13]);
        r.blurred_psnr = csv_number(f[14]);
      } catch (const std::exception&) {
        throw Error("eval --merge: '" + path + "' line " + std::to_string(row) +
                    " holds a field that is not a number");
      }
      results.push_back(r);
    }
    const std::string summary_path = (fs::path(dir) / "summary.json").string();
    nlohmann::json j;
    if (fs::exists(summary_path))
      j = nlohmann::json::parse(
          read_regular_input_file(summary_path, kMaxCsvBytes, "eval --merge: shard summary"),
          nullptr, false);
    if (model.empty()) {
      if (j.is_object() && j.contains("model") && j["model"].is_string()) model = j["model"];
      if (j.is_object() && j.contains("data") && j["data"].is_string()) data = j["data"];
      if (j.is_object() && j.contains("blur_sigma_px") && j["blur_sigma_px"].is_number())
        blur_sigma = j["blur_sigma_px"];
    }
    // Which shard of how many: all of them must be merged, else the figures are of a part.
    if (j.is_object() && j.contains("shard") && j["shard"].is_string()) {
      int index = 0, count = 1;
      parse_shard(j["shard"].get<std::string>(), index, count);
      check(shard_count == 0 || shard_count == count, "eval --merge: '", dir, "' is shard ",
            j["shard"].get<std::string>(), " but another folder is of a run split ", shard_count,
            " ways; merge the shards of one run");
      shard_count = count;
      shards_seen.insert(index);  // a shard given twice is refused below by its repeated rows
    } else {
      ++unlabelled_shards;
    }
  }
  std::sort(results.begin(), results.end(),
            [](const ImageResult& a, const ImageResult& b) { return a.file < b.file; });
  for (size_t i = 1; i < results.size(); ++i)
    check(results[i].file != results[i - 1].file, "eval --merge: '", results[i].file,
          "' is in two shards; merge each shard's output once");
  check(!results.empty(), "eval --merge: the shards hold no images");
  if (shard_count > 0 && unlabelled_shards == 0 &&
      static_cast<int>(shards_seen.size()) != shard_count) {
    std::string missing;
    for (int i = 0; i < shard_count; ++i)
      if (!shards_seen.count(i))
        missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" +
                   std::to_string(shard_count);
    fail("eval --merge: the run was split ", shard_count, " ways but shard(s) ", missing,
         " are not given; merge all of them (the figures of a part are not the run's)");
  }
  if (unlabelled_shards > 0)
    std::cerr << "eval --merge: warning: " << unlabelled_shards << " shard folder(s) do not say "
              << "which shard they are (made by an older facetool); cannot check that none is "
              << "missing\n";
  AngleSums sums;
  for (const ImageResult& r : results) {
    AngleSums image;
    image.pixels = r.pixels;
    image.sum = r.angle_sum;
    image.sum_sq = r.angle_sum_sq;
    image.under20 = r.under20;
    image.under25 = r.under25;
    image.under30 = r.under30;
    sums.add(image);
  }
  const AngularSummary a = sums.summary();
  fs::create_directories(out_dir);
  const FolderLock lock(out_dir, "-o");  // one run per output folder
  std::cout << write_outputs(out_dir, model, data, results, a, blur_sigma);
  std::cerr << "merged " << shards.size() << " shards, " << results.size() << " images\n";
  return 0;
}

int run_eval(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  std::string model, data, out_dir, shard = "0/1";
  std::vector<std::string> merge;
  int batch = 8;
  double blur_sigma = 1.0;
  options.add_options()
      ("model", po::value(&model)->value_name("WEIGHTS"), "trained weights (default: the shipped model)")
      ("data", po::value(&data)->value_name("DIR"),
       "folder of sample_*.exr (synthetic: with ground truth; real: reconstruction only)")
      ("output,o", po::value(&out_dir)->value_name("DIR")->required(),
       "writes per_image.csv, summary.json, summary.md")
      ("batch", po::value(&batch)->default_value(8), "images per network run")
      ("blur-sigma", po::value(&blur_sigma)->value_name("PX")->default_value(1.0),
       "the baseline beside the reconstruction's PSNR: the input blurred by a Gaussian of this "
       "standard deviation (pixels of the sample), against the input")
      ("shard", po::value(&shard)->value_name("i/n")->default_value("0/1"),
       "evaluate only the samples i, i+n, i+2n, ... of the sorted list (Slurm array jobs)")
      ("merge", po::value(&merge)->value_name("DIR")->multitoken(),
       "merge these shards' outputs (eval --shard i/n -o DIR) into -o: per_image.csv and the "
       "summary, as one unsharded run writes them")
      ("contact-sheet", "also write contact_sheet.png: input, reconstruction, normal, true normal");
  add_mirror_average_option(options);
  add_landmark_head_options(options);
  po::variables_map values;
  if (!parse_command_options(
          "eval [--model WEIGHTS] --data DIR -o OUT [--contact-sheet] [--shard i/n]\n"
          "       facetool eval --merge SHARD_DIR... -o OUT",
          "Evaluates a trained network. On synthetic samples (ground truth): the paper's Table 1 "
          "(normal angular\nerror mean +- std, % of pixels under 20, 25, 30 degrees), albedo and "
          "visibility MSE, light error E_L,\nand reconstruction PSNR and SSIM; on real samples "
          "(facetool-real-1, pseudo labels are not truth)\nPSNR and SSIM only. Beside the PSNR, "
          "that of the input blurred by --blur-sigma (a reconstruction\nbelow it is blurrier "
          "than that). Everything is "
          "measured in the face mask eroded by one pixel.",
          options, {}, args, values))
    return 0;
  check_option_ranges(values, {{"batch", 1, 1024}, {"blur-sigma", 0, 100}});
  if (!merge.empty()) {
    if (!model.empty() || !data.empty() || values.count("contact-sheet"))
      throw UsageError("eval: --merge takes only shard folders and -o");
    return merge_shards(merge, out_dir);
  }
  if (data.empty()) throw UsageError("eval: --data DIR is required");
  if (model.empty()) model = default_model_path();
  int shard_index = 0, shard_count = 1;
  parse_shard(shard, shard_index, shard_count);
  if (batch < 1) throw UsageError("eval: --batch must be at least 1");
  check_not_another_shards_folder(
      out_dir, shard_count > 1 ? std::to_string(shard_index) + "/" + std::to_string(shard_count) : "");
  // A sample that cannot be read (a dangling link, a link loop, a pipe) is refused, not skipped:
  // the figures would silently be of fewer samples.
  std::vector<std::string> problems;
  std::vector<std::string> files = list_folder_files(
      data, "eval: data folder",
      [](const std::string& name) {
        return name.rfind("sample_", 0) == 0 && fs::path(name).extension() == ".exr";
      },
      problems);
  check(problems.empty(), "eval: sample ", problems.empty() ? "" : problems[0],
        problems.size() > 1 ? " (and " + std::to_string(problems.size() - 1) + " more)" : "",
        "; fix or remove it");
  check(!files.empty(), "eval: '", data, "' holds no sample_*.exr files");
  if (shard_count > 1) {
    std::vector<std::string> mine;
    for (size_t k : shard_positions(files.size(), shard_index, shard_count)) mine.push_back(files[k]);
    files = std::move(mine);
    check(!files.empty(), "eval: shard ", shard, " of '", data, "' holds no samples (only ",
          "fewer samples than shards)");
  }

  Backend& backend = get_backend(context.backend);
  const LoadedNetwork loaded = load_trained_network(context, backend, model);
  const std::shared_ptr<NetworkPlugin> network = loaded.network;
  auto renderer = create_plugin<RendererPlugin>(context, FACETOOL_PLUGIN_RENDERER, "sh_renderer");
  Decomposer decomposer(*network, *renderer);
  apply_landmark_head_options(values, decomposer, loaded);
  apply_mirror_average_option(values, decomposer);
  const int size = network->config().input_size;
  const size_t plane = static_cast<size_t>(size) * size;
  fs::create_directories(out_dir);
  const FolderLock lock(out_dir, "-o");  // one run per output folder

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
  std::vector<TrainingSample> samples;  // the batch's
  decompose_in_batches(
      decomposer, backend, files.size(), batch,
      [&](size_t k, std::vector<float>& planes) {
        if (planes.empty()) samples.clear();
        samples.push_back(read_training_sample(files[k], false, network->config().input_prior));
        const TrainingSample& s = samples.back();
        check_sample_size(files[k], s.width, s.height, loaded);
        planes.insert(planes.end(), s.image.begin(), s.image.end());
        planes.insert(planes.end(), s.prior.begin(), s.prior.end());  // the input prior, if any
      },
      [&](size_t first, const Decomposition& d, const std::vector<float>&) {
        const int count = d.count;
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
          r.blurred_psnr = masked_psnr(gaussian_blur(s.image, 3, size, size, blur_sigma).data(),
                                       s.image.data(), mask.data(), size, size);
          if (r.truth) {
            std::vector<double> own;
            normal_angles_deg(normal, s.normal.data(), mask.data(), plane, own);
            r.normal_mean = summarize_angles(own).mean;
            angles.insert(angles.end(), own.begin(), own.end());
            for (double angle : own) {
              ++r.pixels;
              r.angle_sum += angle;
              r.angle_sum_sq += angle * angle;
              r.under20 += angle < 20.0;
              r.under25 += angle < 25.0;
              r.under30 += angle < 30.0;
            }
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
      },
      [&](size_t, std::vector<float>& points) {  // for the landmark normal head (the sample just loaded)
        const std::vector<float>& own = samples.back().landmarks;
        points.insert(points.end(), own.begin(), own.end());
        return !own.empty();
      });
  progress.finish();

  const std::string md_text =
      write_outputs(out_dir, model, data, results, summarize_angles(angles), blur_sigma,
                    shard_count > 1
                        ? std::to_string(shard_index) + "/" + std::to_string(shard_count)
                        : "");
  if (want_sheet) write_png_atomically((fs::path(out_dir) / "contact_sheet.png").string(), sheet);
  std::cout << md_text;
  return 0;
}

const CommandRegistration registration{
    {"eval", "evaluate a trained network: normal error (Table 1), PSNR/SSIM, per-image CSV",
     run_eval}};

}  // namespace
}  // namespace facetool
