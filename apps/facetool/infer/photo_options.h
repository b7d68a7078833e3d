// The photo options of `infer`, `relight` and `prepare-real` as command-line options.
#pragma once

#include <boost/program_options.hpp>
#include <vector>

#include "apps/facetool/commands/command_options.h"
#include "libs/photo/photo_pipeline.h"

namespace facetool {

// The photo options of `infer` (also used by prepare-real and relight for the detection ones).
void add_photo_detection_options(boost::program_options::options_description& options);
void add_photo_infer_options(boost::program_options::options_description& options);
// Valid ranges of the detection and paste-back options (for check_option_ranges).
std::vector<OptionRange> photo_option_ranges();
PhotoInferOptions photo_options_from(const boost::program_options::variables_map& values);

}  // namespace facetool
