// The generation loop: workers pull sample indices, skip finished files, write new ones.
#include "libs/synth/synth_runner.h"

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <system_error>
#include <thread>

#include "core/util/atomic_file.h"
#include "libs/synth/contact_sheet.h"
#include "core/util/error.h"
#include "core/util/folder_lock.h"
#include "core/util/memory_budget.h"

namespace facetool {
namespace fs = std::filesystem;

namespace {

double process_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

std::string manifest_line(const std::string& file, const SynthSampleInfo& info) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), "%s\t%lld\t%llu\t%.6f\t%.6f\t%.6f\t%.6f\t", file.c_str(),
                static_cast<long long>(info.index), static_cast<unsigned long long>(info.sample_seed),
                info.pose.roll_deg, info.pose.pitch_deg, info.pose.yaw_deg, info.fov_deg);
  return buffer + info.light_source + "\n";
}

SynthSampleInfo info_of(const SynthSample& s) {
  SynthSampleInfo info;
  info.generator_version = kSynthGeneratorVersion;
  info.run_seed = s.run_seed;
  info.sample_seed = s.sample_seed;
  info.index = s.index;
  info.width = s.width;
  info.height = s.height;
  info.pose = s.pose;
  info.fov_deg = s.fov_deg;
  info.light_source = s.light_source;
  return info;
}

// Memory one worker needs for a sample, per pixel: the sample's 20 float planes, the ray-cast
// G-buffer and the EXR being encoded (measured: peak resident memory grows by 296 bytes per
// pixel from 256x256 to 1024x1024 with one thread).
constexpr uint64_t kSampleBytesPerPixel = 300;

}  // namespace

SynthRunReport run_synth(const SampleGenerator& generator, const SynthRunOptions& options) {
  check(options.count >= 0, "--count must not be negative");
  check(options.shard_count > 0 && options.shard_index >= 0 &&
            options.shard_index < options.shard_count,
        "shard ", options.shard_index, "/", options.shard_count, " is not valid");
  check(options.threads > 0, "--threads must be positive, got ", options.threads);
  check(!options.output_dir.empty(), "no output folder given (--out DIR)");
  std::error_code error;
  fs::create_directories(options.output_dir, error);
  check(fs::is_directory(options.output_dir), "cannot create output folder '",
        options.output_dir, "': ", error.message());
  // One run per folder; the shards of one sharded run write disjoint samples and share it.
  const FolderLock lock(options.output_dir, "--out", options.shard_index, options.shard_count);
  remove_stale_temporary_files(options.output_dir);

  std::vector<int64_t> indices;
  for (int64_t k = options.shard_index; k < options.count; k += options.shard_count)
    indices.push_back(k);
  std::vector<SynthSampleInfo> infos(indices.size());
  const int width = generator.settings().camera.width, height = generator.settings().camera.height;
  const uint64_t sample_bytes = static_cast<uint64_t>(width) * height * kSampleBytesPerPixel;
  const std::string sample_what = "generating a " + std::to_string(width) + "x" +
                                  std::to_string(height) + " synthetic sample";
  // At least one sample must fit before anything is written; more threads only as many as fit.
  if (!indices.empty()) check_memory_budget(sample_bytes, sample_what);
  const uint64_t fitting = std::max<uint64_t>(available_memory_bytes() / sample_bytes, 1);

  SynthRunReport report;
  std::atomic<size_t> next{0};
  std::atomic<int64_t> generated{0}, reused{0}, repaired{0}, rays{0}, done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr first_error;
  std::mutex mutex;
  auto worker = [&] {
    for (;;) {
      const size_t position = next++;
      if (position >= indices.size() || stop) return;
      try {
        const int64_t index = indices[position];
        const std::string path = (fs::path(options.output_dir) / sample_file_name(index)).string();
        bool have = false;
        if (fs::exists(path)) {
          // A present sample is kept only when it was made the same way (its metadata) and
          // is whole (all pixels decode); a damaged one is made again; one made with other
          // settings is an error, or is made again with options.overwrite.
          SynthSampleInfo info;
          bool readable = true;
          try {
            info = read_synth_sample_info(path);
          } catch (const Error&) {
            readable = false;
          }
          const bool same_run = readable && info.run_seed == options.seed &&
                                info.index == index &&
                                info.generator_version == kSynthGeneratorVersion &&
                                info.width == width && info.height == height &&
                                info.settings == generator.settings_fingerprint();
          if (readable && !same_run && !options.overwrite)
            fail("output folder '", options.output_dir, "' already holds ", path,
                 " made with other settings (seed ", info.run_seed, ", ", info.width, "x",
                 info.height, ", ", info.generator_version, ", settings ",
                 info.settings.empty() ? "not recorded" : info.settings, "; this run: seed ",
                 options.seed, ", ", width, "x", height, ", settings ",
                 generator.settings_fingerprint(),
                 ", listed in the manifest); use a new folder, the same settings, or "
                 "--overwrite to regenerate such samples");
          bool whole = false;
          if (same_run) {
            try {
              read_synth_sample(path);
              whole = true;
            } catch (const Error&) {
              ++repaired;  // truncated or damaged pixels: make it again
            }
          } else if (!readable) {
            ++repaired;
          }
          if (whole) {
            infos[position] = info;
            have = true;
            ++reused;
          }
        }
        if (!have) {
          naming_out_of_memory(sample_what + " (index " + std::to_string(index) + ")",
                               sample_bytes, [&] {
                                 const SynthSample sample = generator.generate(options.seed, index);
                                 write_synth_sample(path, sample);
                                 infos[position] = info_of(sample);
                                 rays += sample.rays_cast;
                               });
          ++generated;
        }
        const int64_t finished = ++done;
        if (options.progress) {
          std::lock_guard<std::mutex> lock(mutex);
          options.progress(finished, static_cast<int64_t>(indices.size()));
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!first_error) first_error = std::current_exception();
        stop = true;
        return;
      }
    }
  };
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  std::vector<std::thread> pool;
  const int thread_count = static_cast<int>(std::min<uint64_t>(
      std::min<size_t>(options.threads, std::max<size_t>(indices.size(), 1)), fitting));
  // A thread the system cannot give (memory or process limits) is done without: the workers
  // already started and this thread share the samples.
  for (int t = 1; t < thread_count; ++t) {
    try {
      pool.emplace_back(worker);
    } catch (const std::system_error&) {
      break;
    }
  }
  worker();
  for (std::thread& thread : pool) thread.join();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.cpu_seconds = process_cpu_seconds() - cpu_start;
  if (first_error) std::rethrow_exception(first_error);
  report.generated = generated;
  report.reused = reused;
  report.repaired = repaired;
  report.rays_cast = rays;

  // Manifest of this shard.
  std::ostringstream manifest;
  manifest << "# facetool synth manifest: generator " << kSynthGeneratorVersion << ", seed "
           << options.seed << ", count " << options.count << ", shard " << options.shard_index
           << "/" << options.shard_count << ", " << width << "x" << height << ", "
           << generator.settings().direction_count << " visibility directions\n"
           << "# settings " << generator.settings_fingerprint() << ":\n";
  std::istringstream description(generator.settings_description());
  for (std::string line; std::getline(description, line);) manifest << "#   " << line << "\n";
  manifest << "file\tindex\tsample_seed\troll_deg\tpitch_deg\tyaw_deg\tfov_deg\tlight_source\n";
  for (size_t k = 0; k < indices.size(); ++k)
    manifest << manifest_line(sample_file_name(indices[k]), infos[k]);
  char manifest_name[64];
  std::snprintf(manifest_name, sizeof(manifest_name), "manifest-%d-of-%d.tsv",
                options.shard_index, options.shard_count);
  report.manifest_path = (fs::path(options.output_dir) / manifest_name).string();
  const std::string text = manifest.str();
  write_file_atomically(report.manifest_path, text.data(), text.size());

  if (!options.contact_sheet.empty() && !indices.empty()) {
    std::vector<SynthSample> rows;
    const size_t row_count = std::min<size_t>(indices.size(), std::max(options.contact_sheet_rows, 1));
    for (size_t k = 0; k < row_count; ++k)
      rows.push_back(read_synth_sample(
          (fs::path(options.output_dir) / sample_file_name(indices[k])).string()));
    write_contact_sheet(options.contact_sheet, rows);
  }
  return report;
}

}  // namespace facetool
