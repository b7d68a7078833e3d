// The options of the landmark fit shared by `facetool fit` and `facetool infer --with-fit`.
#pragma once

#include <boost/program_options.hpp>
#include <vector>

#include "apps/facetool/commands/command_options.h"
#include "libs/fit/photo_fit.h"

namespace facetool {

// --camera, --fov, --jaw, --identity-prior, --expression-prior, --no-expressions, --directions,
// --no-visibility.
void add_fit_options(boost::program_options::options_description& options);
std::vector<OptionRange> fit_option_ranges();
// Throws UsageError for an unknown --camera or --jaw.
PhotoFitOptions fit_options_from(const boost::program_options::variables_map& values);

}  // namespace facetool
