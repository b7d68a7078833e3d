// The output option every writing command shares: -o / --output, with --out kept as an alias.
#pragma once

#include <boost/program_options.hpp>
#include <string>

namespace facetool {

// Adds "-o [ --output ] VALUE_NAME" to `options` (shown in --help, with a note that --out is
// accepted too) and the alias "--out" to `hidden`; both store into `target`.
void add_output_option(boost::program_options::options_description& options,
                       boost::program_options::options_description& hidden, std::string* target,
                       const std::string& value_name, const std::string& description);

// After parsing: throws UsageError when both spellings were given, or when none was and
// `what` (e.g. "an output folder with -o DIR") is required.
void check_output_option(const boost::program_options::variables_map& values,
                         const std::string& command, const std::string& what);

// Before any work: throws facetool::Error naming `option` when the folder `file` would be
// written into does not exist or is not a folder, or when `file` itself is a folder or another
// file that is not regular (a device, a pipe, a socket).
void check_output_file_location(const std::string& file, const std::string& option);

}  // namespace facetool
