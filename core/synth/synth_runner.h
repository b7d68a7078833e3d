// Running the generator over many samples: sharding, worker threads, resume, manifest,
// contact sheet, and progress reporting.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/synth/sample_generator.h"

namespace facetool {

struct SynthRunOptions {
  std::string output_dir;
  int64_t count = 0;       // samples in the whole run (all shards)
  uint64_t seed = 0;
  int shard_index = 0;     // this process makes the samples with index % shard_count == shard_index
  int shard_count = 1;
  int threads = 1;
  std::string contact_sheet;  // PNG path, empty for none
  int contact_sheet_rows = 16;
  // Called after every finished sample (generated or found) with (done, total of this shard).
  std::function<void(int64_t done, int64_t total)> progress;
};

struct SynthRunReport {
  int64_t generated = 0;  // written by this run
  int64_t reused = 0;     // already present from an earlier run (resume)
  int64_t rays_cast = 0;  // visibility rays of the generated samples
  double seconds = 0;     // wall time of the generation loop
  double cpu_seconds = 0; // CPU time of the process during the loop (all threads)
  std::string manifest_path;
};

// Generates the shard's missing samples into options.output_dir (created if needed), each as
// synth_sample_file_name(index) written atomically, so an interrupted run leaves only whole
// files and resumes where it stopped. A present sample is kept when its header names the same
// generator version and seed; a present sample of another seed is an error (use another
// folder); an unreadable one is regenerated. Then writes manifest-<i>-of-<n>.tsv and the
// contact sheet. Output is bit-identical whatever the thread count.
SynthRunReport run_synth(const SampleGenerator& generator, const SynthRunOptions& options);

// Parses "i/n" (0 <= i < n); throws facetool::Error otherwise.
void parse_shard(const std::string& text, int& index, int& count);

}  // namespace facetool
