// Photo-pipeline benchmarks: detection, landmarks, alignment and paste-back per photo.
#pragma once

#include <ostream>
#include <string>

namespace facetool {

// Times the steps around the network for `photo_path` (one face) at its own size and scaled up
// to about 12 megapixels; prints medians of `repeats` runs.
void run_photo_benchmarks(const std::string& photo_path, int crop_size, int repeats, std::ostream& out);

}  // namespace facetool
