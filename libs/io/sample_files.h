// The sample EXR files of synth, prepare-real and pseudo-label (read by train and eval): their
// file names and the real samples' format version, defined once for every library.
#pragma once

#include <cstdint>
#include <string>

namespace facetool {

// facetool:generator_version of real samples (facetool prepare-real, facetool pseudo-label);
// synthetic samples carry kSynthGeneratorVersion (libs/synth/synth_sample.h).
inline constexpr const char* kRealSampleVersion = "facetool-real-1";

// File name of sample `index`: "sample_00000042.exr".
std::string sample_file_name(int64_t index);

}  // namespace facetool
