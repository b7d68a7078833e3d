// `facetool backends`: every compute backend, whether it can run here and why not, its devices.
#include <iostream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"
#include "core/backend/registry.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

// Writes `text` with every line after the first indented by `indent` spaces.
void print_indented(std::ostream& out, const std::string& text, size_t indent) {
  for (char c : text) {
    out << c;
    if (c == '\n') out << std::string(indent, ' ');
  }
}

int run_backends(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  po::variables_map values;
  if (!parse_command_options("backends [options]",
                             "Lists the compute backends facetool knows, whether each can run on "
                             "this machine (and if not, why),\nand every device with the index "
                             "to select it (--backend opencl:<index>).",
                             options, po::positional_options_description(), args, values))
    return 0;
  check_option_ranges(values, {});  // no numeric options (a new one must get a range)

  const std::string selected = context.backend.substr(0, context.backend.find(':'));
  const std::vector<BackendInfo> backends = list_backends();
  size_t width = 4;
  for (const BackendInfo& info : backends) width = std::max(width, info.name.size());
  std::cout << "  " << "NAME" << std::string(width - 4 + 2, ' ') << "STATUS       DETAILS\n";
  for (const BackendInfo& info : backends) {
    const std::string marker = info.name == selected ? "* " : "  ";
    std::cout << marker << info.name << std::string(width - info.name.size() + 2, ' ')
              << (info.available ? "available    " : "unavailable  ");
    const size_t details_column = 2 + width + 2 + 13;
    if (info.available) {
      std::cout << info.devices.size() << (info.devices.size() == 1 ? " device" : " devices")
                << '\n';
      for (const std::string& device : info.devices)
        std::cout << std::string(details_column + 2, ' ') << device << '\n';
    } else {
      print_indented(std::cout, info.reason, details_column);
      std::cout << '\n';
    }
  }
  std::cout << "\n* = selected (--backend " << context.backend << ")\n";
  return 0;
}

const CommandRegistration registration{
    {"backends", "list compute backends, whether they can run here, and their devices",
     run_backends}};

}  // namespace
}  // namespace facetool
