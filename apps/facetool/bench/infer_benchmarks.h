// `bench infer`: whole photos through `infer`'s pipeline, timed stage by stage.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "core/backend/backend.h"
#include "libs/inference/decomposer.h"
#include "libs/photo/photo_pipeline.h"

namespace facetool {

struct InferBenchOptions {
  std::vector<std::string> photos;  // files (folders already expanded)
  std::string out_dir;              // where infer writes (the caller removes it)
  int crop_size = 64;
  int repeats = 1;  // passes over all photos; stage figures are per photo over all passes
  PhotoInferOptions photo;
};

// Runs infer_photos once over the photos listed `repeats` times, writing options.photo.outputs
// (with only the layers they need pasted back, options.photo.layers), and
// prints photos/s and each stage's ms per photo (load models, decode, detect, landmarks, align,
// fit prior, network, render, paste-back, encode, write, fsync) and the part no stage accounts for.
void run_infer_benchmarks(Decomposer& decomposer, Backend& backend,
                          const InferBenchOptions& options, std::ostream& out);

}  // namespace facetool
