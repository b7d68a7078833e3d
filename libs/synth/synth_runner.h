// Running the generator over many samples: sharding, worker threads, resume, manifest,
// contact sheet, and progress reporting.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "libs/synth/sample_generator.h"

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
  // Regenerate present samples made with other settings instead of refusing to continue.
  bool overwrite = false;
  // Called after every finished sample (generated or found) with (done, total of this shard).
  std::function<void(int64_t done, int64_t total)> progress;
};

struct SynthRunReport {
  int64_t generated = 0;  // written by this run
  int64_t reused = 0;     // already present from an earlier run (resume), whole and the same
  int64_t repaired = 0;   // present but damaged (unreadable header or pixels): made again
  int64_t rays_cast = 0;  // visibility rays of the generated samples
  double seconds = 0;     // wall time of the generation loop
  double cpu_seconds = 0; // CPU time of the process during the loop (all threads)
  std::string manifest_path;
};

// Generates the shard's missing samples into options.output_dir (created if needed), each as
// sample_file_name(index) written atomically, so an interrupted run leaves only whole
// files and resumes where it stopped. A present sample is kept when its header names the same
// generator version, seed, size and settings fingerprint (generator_settings.h: lights, faces,
// sampling, renderer...) and all its pixels decode; a damaged one (truncated, unreadable) is
// regenerated; one made with other settings is an error (use another folder) unless
// options.overwrite, which regenerates it. Then writes manifest-<i>-of-<n>.tsv (with the
// settings) and the contact sheet. Output is bit-identical whatever the thread count.
SynthRunReport run_synth(const SampleGenerator& generator, const SynthRunOptions& options);

}  // namespace facetool
