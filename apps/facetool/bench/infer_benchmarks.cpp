// `bench infer`: infer_photos with stage timing switched on (core/util/stage_timer.h).
#include "apps/facetool/bench/infer_benchmarks.h"

#include <chrono>
#include <cstdio>

#include "core/util/cpu_time.h"
#include "libs/photo/photo_files.h"
#include "core/util/output_names.h"
#include "core/util/stage_timer.h"

namespace facetool {

void run_infer_benchmarks(Decomposer& decomposer, Backend& backend,
                          const InferBenchOptions& options, std::ostream& out) {
  out << "infer on " << options.photos.size() << " photo(s), crop " << options.crop_size
      << ", batch " << options.photo.batch << ", "
      << (options.photo.outputs.is_all() ? std::string("every output written")
                                         : "outputs " + options.photo.outputs.names() + " (and faces.json)")
      << ", each photo "
      << options.repeats << " time(s) in one run, after one warm-up photo\n";
  const std::unique_ptr<FaceDetector> detector = make_face_detector(options.photo);
  PhotoDecomposer photo_decomposer(*detector, decomposer, backend, options.crop_size, options.photo);
  auto run = [&](const std::vector<std::string>& photos, const std::string& dir) {
    return infer_photos(photos, unique_output_names(photos), dir, photo_decomposer, options.photo);
  };
  // Warm-up: the first photo once (plugin kernels, caches; the models are loaded above).
  run({options.photos.front()}, options.out_dir + "/warmup");
  // One infer_photos call over the photos `repeats` times (outputs get numbered folders), as
  // one `infer` run on a folder.
  std::vector<std::string> all;
  for (int r = 0; r < options.repeats; ++r)
    all.insert(all.end(), options.photos.begin(), options.photos.end());
  reset_stage_totals();
  enable_stage_timing(true);
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = process_cpu_seconds();
  const int failed = run(all, options.out_dir + "/run");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu_seconds = process_cpu_seconds() - cpu_start;
  enable_stage_timing(false);
  const double photos = static_cast<double>(options.photos.size()) * options.repeats;
  char line[200];
  // The CPU time (all threads) moves far less than the wall time on a shared machine.
  std::snprintf(line, sizeof line, "%.2f photos/s, %.1f ms per photo end to end, %.1f CPU ms per photo%s\n",
                photos / seconds, 1e3 * seconds / photos, 1e3 * cpu_seconds / photos,
                failed ? " (some photos had no face: see above)" : "");
  out << line;
  // The stages of one photo's files (encode, write, fsync) run on infer's writer thread while
  // the next photo is decoded, detected and run through the network: the stage times add up to
  // more than the wall time, so shares are of their sum.
  double staged = 0.0;
  for (const StageTotal& t : stage_totals()) staged += t.seconds;
  std::snprintf(line, sizeof line, "%-14s %12s %8s %8s\n", "stage", "ms/photo", "share", "calls");
  out << line;
  for (const StageTotal& t : stage_totals()) {
    std::snprintf(line, sizeof line, "%-14s %12.2f %7.1f%% %8ld\n", t.stage.c_str(),
                  1e3 * t.seconds / photos, staged > 0 ? 100.0 * t.seconds / staged : 0.0, t.calls);
    out << line;
  }
  std::snprintf(line, sizeof line,
                "stages in all %.2f ms per photo on two threads (the writer overlaps the rest), "
                "wall %.2f ms\n", 1e3 * staged / photos, 1e3 * seconds / photos);
  out << line << std::flush;
}

}  // namespace facetool
