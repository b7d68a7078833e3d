// `facetool plugins`: the plugin search path, every plugin found, and files that failed to load.
#include <filesystem>
#include <iostream>

#include "apps/facetool/commands/command.h"
#include "apps/facetool/commands/command_options.h"

namespace po = boost::program_options;

namespace facetool {
namespace {

int run_plugins(CommandContext& context, const std::vector<std::string>& args) {
  po::options_description options("Options");
  po::variables_map values;
  if (!parse_command_options(
          "plugins [--plugin FILE]...",
          "Lists the folders searched for *" FACETOOL_PLUGIN_FILE_SUFFIX
          " plugins (FACETOOL_PLUGIN_PATH, then beside the\nexecutable, then "
          "<executable>/../lib/facetool/plugins), every plugin found or given with\n--plugin, "
          "and every file that could not be loaded with the reason.",
          options, po::positional_options_description(), args, values))
    return 0;
  check_option_ranges(values, {});  // no numeric options (a new one must get a range)

  // Unlike other commands, a bad --plugin file is listed with the other problems, not fatal.
  PluginLoader loader;
  std::vector<std::string> problems;
  for (const std::string& file : context.plugin_files) {
    try {
      loader.load_file(file);
    } catch (const Error& e) {
      problems.push_back(e.what());
    }
  }
  const size_t explicit_failures = problems.size();
  loader.discover();
  problems.insert(problems.end(), loader.problems().begin(), loader.problems().end());

  std::cout << "Search path:\n";
  for (const std::string& dir : loader.search_dirs()) {
    std::error_code ec;
    std::cout << "  " << dir << (std::filesystem::is_directory(dir, ec) ? "" : "  (missing)")
              << '\n';
  }

  std::cout << "\nPlugins (" << loader.plugins().size() << "):\n";
  if (loader.plugins().empty()) std::cout << "  none\n";
  for (const PluginInfo& info : loader.plugins()) {
    std::cout << "  " << info.name << ' ' << info.version << "  [" << plugin_kind_name(info.kind)
              << "]\n"
              << "      " << info.description << '\n'
              << "      file: " << info.path << '\n'
              << "      built with: " << (info.compiler.empty() ? "?" : info.compiler) << '\n';
  }

  if (!problems.empty()) {
    std::cout << "\nProblems (" << problems.size() << "):\n";
    for (const std::string& problem : problems) std::cout << "  - " << problem << '\n';
  }
  return explicit_failures > 0 ? 1 : 0;
}

const CommandRegistration registration{
    {"plugins", "list the plugin search path, the plugins found, and files that failed to load",
     run_plugins}};

}  // namespace
}  // namespace facetool
