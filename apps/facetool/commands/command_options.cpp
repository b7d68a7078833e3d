// Option parsing shared by main() and the commands.
#include "apps/facetool/commands/command_options.h"

#include <cmath>
#include <cstdint>
#include <iostream>
#include <optional>
#include <sstream>

namespace po = boost::program_options;

namespace facetool {

po::options_description common_options() {
  po::options_description options("Common options (before or after the command)");
  options.add_options()
      ("backend", po::value<std::string>()->value_name("NAME"),
       "compute backend: cpu (default), opencl, opencl:<index>, opencl:<device name part>")
      ("plugin", po::value<std::vector<std::string>>()->value_name("FILE"),
       "load a plugin library (repeatable)")
      ("verbose,v", po::bool_switch(), "print more about what facetool does");
  return options;
}

int option_style() {
  return po::command_line_style::default_style & ~po::command_line_style::allow_guessing;
}

namespace {

// boost's lexical_cast turns "-1" into 2^64 - 1 for an unsigned option, which would pass its
// range check: a minus sign given to an unsigned option is refused here, naming the option.
void refuse_negative_unsigned(const po::parsed_options& parsed, const po::variables_map& values) {
  for (const po::option& option : parsed.options) {
    const auto found = values.find(option.string_key);
    if (found == values.end()) continue;
    const boost::any& value = found->second.value();
    if (!boost::any_cast<uint64_t>(&value) && !boost::any_cast<unsigned>(&value)) continue;
    for (const std::string& token : option.value)
      if (token.find('-') != std::string::npos)
        throw UsageError("--" + option.string_key + " must be a whole number 0 or more; got '" +
                         token + "'");
  }
}

}  // namespace

bool parse_command_options(const std::string& usage, const std::string& description,
                           po::options_description& options,
                           const po::positional_options_description& positional,
                           const std::vector<std::string>& args, po::variables_map& values,
                           const po::options_description& hidden) {
  options.add_options()("help,h", "show this command's options");
  po::options_description all;
  all.add(options).add(hidden);
  const po::parsed_options parsed = po::command_line_parser(args)
                                        .options(all)
                                        .positional(positional)
                                        .style(option_style())
                                        .run();
  po::store(parsed, values);
  refuse_negative_unsigned(parsed, values);
  if (values.count("help")) {
    std::cout << "usage: facetool " << usage << "\n\n" << description << "\n\n"
              << options << '\n'
              << common_options();
    return false;
  }
  po::notify(values);
  return true;
}

namespace {

// The value of a numeric option as a double, or nothing for other types (strings, lists).
std::optional<double> numeric_value(const boost::any& value) {
  if (const int* v = boost::any_cast<int>(&value)) return *v;
  if (const int64_t* v = boost::any_cast<int64_t>(&value)) return static_cast<double>(*v);
  if (const uint64_t* v = boost::any_cast<uint64_t>(&value)) return static_cast<double>(*v);
  if (const unsigned* v = boost::any_cast<unsigned>(&value)) return *v;
  if (const float* v = boost::any_cast<float>(&value)) return *v;
  if (const double* v = boost::any_cast<double>(&value)) return *v;
  return std::nullopt;
}

std::string number_text(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

}  // namespace

void check_option_ranges(const po::variables_map& values, const std::vector<OptionRange>& ranges) {
  for (const auto& [name, variable] : values) {
    const std::optional<double> value = numeric_value(variable.value());
    if (!value) continue;
    const OptionRange* range = nullptr;
    for (const OptionRange& r : ranges)
      if (r.name == name) range = &r;
    check(range != nullptr, "internal: numeric option --", name,
          " has no valid range; add it to the command's check_option_ranges call");
    if (!std::isfinite(*value) || *value < range->min || *value > range->max)
      throw UsageError("--" + name + " must be a finite number in [" + number_text(range->min) +
                       ", " + number_text(range->max) + "]; got " + number_text(*value));
  }
}

std::vector<int> parse_positive_int_list(const std::string& text, const std::string& option) {
  std::vector<int> numbers;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    const std::string part = text.substr(start, end - start);
    size_t used = 0;
    int value = 0;
    try {
      value = std::stoi(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (part.empty() || used != part.size() || value <= 0)
      throw UsageError("--" + option + " expects a comma-separated list of positive integers " +
                       "such as 1,20; got '" + text + "'");
    numbers.push_back(value);
    start = end + 1;
  }
  return numbers;
}

}  // namespace facetool
