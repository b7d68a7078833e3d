// Option parsing shared by main() and the commands (boost::program_options).
#pragma once

#include <boost/program_options.hpp>
#include <string>
#include <vector>

#include "apps/facetool/commands/command.h"

namespace facetool {

// Options accepted before or after the command name: --backend, --plugin, --verbose.
boost::program_options::options_description common_options();

// Parses a command's arguments against `options` (to which --help is added) and `hidden` (options
// left out of the help, typically the targets of positional arguments). Returns false after
// printing the command's help to stdout when --help is given; the caller then returns 0.
// `usage` follows "facetool ", e.g. "bench <target> [options]".
bool parse_command_options(const std::string& usage, const std::string& description,
                           boost::program_options::options_description& options,
                           const boost::program_options::positional_options_description& positional,
                           const std::vector<std::string>& args,
                           boost::program_options::variables_map& values,
                           const boost::program_options::options_description& hidden = {});

// The parser style facetool uses everywhere: the default, without guessing abbreviations.
int option_style();

// The valid range [min, max] of one numeric option (`name` without the leading dashes).
struct OptionRange {
  std::string name;
  double min;
  double max;
};

// Checks every numeric option in `values` (int, int64_t, uint64_t, float, double; given or
// defaulted): each must be finite and within its range, else UsageError "--NAME must be a
// finite number in [MIN, MAX]; got VALUE". A numeric option with no range in `ranges` is a
// programming error (facetool::Error), so no command can forget one.
void check_option_ranges(const boost::program_options::variables_map& values,
                         const std::vector<OptionRange>& ranges);

// Splits "1,20,64" into positive integers; throws UsageError naming `option` otherwise.
std::vector<int> parse_positive_int_list(const std::string& text, const std::string& option);

}  // namespace facetool
