// Option parsing shared by main() and the commands.
#include "apps/facetool/commands/command_options.h"

#include <iostream>

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

bool parse_command_options(const std::string& usage, const std::string& description,
                           po::options_description& options,
                           const po::positional_options_description& positional,
                           const std::vector<std::string>& args, po::variables_map& values,
                           const po::options_description& hidden) {
  options.add_options()("help,h", "show this command's options");
  po::options_description all;
  all.add(options).add(hidden);
  po::store(po::command_line_parser(args)
                .options(all)
                .positional(positional)
                .style(option_style())
                .run(),
            values);
  if (values.count("help")) {
    std::cout << "usage: facetool " << usage << "\n\n" << description << "\n\n"
              << options << '\n'
              << common_options();
    return false;
  }
  po::notify(values);
  return true;
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
