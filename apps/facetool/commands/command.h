// Command: one `facetool <name>` subcommand, the context it runs in, and the command registry.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/plugin/plugin_loader.h"
#include "core/util/error.h"

namespace facetool {

// A mistake in how facetool was invoked (unknown command, bad option value): exit code 2.
class UsageError : public Error {
 public:
  using Error::Error;
};

// What every command gets from the options common to all commands (common_options() in command_options.h).
class CommandContext {
 public:
  std::string backend = "cpu";            // --backend
  std::vector<std::string> plugin_files;  // --plugin, in the order given
  bool verbose = false;                   // --verbose

  // The plugin loader, created on first use: the --plugin files loaded (an error in one of them
  // throws), then the search path discovered (problems there are printed with --verbose).
  PluginLoader& plugins();

 private:
  std::unique_ptr<PluginLoader> plugins_;
};

// Creates plugin `name` of `kind` (loading the plugins on first use) and checks that its object
// implements `Interface` (NetworkPlugin, RendererPlugin, ...).
template <typename Interface>
std::shared_ptr<Interface> create_plugin(CommandContext& context, uint32_t kind,
                                         const std::string& name) {
  PluginLoader& loader = context.plugins();
  auto plugin = std::dynamic_pointer_cast<Interface>(loader.create(loader.find(kind, name)));
  check(plugin != nullptr, "plugin '", name, "' does not implement the ", plugin_kind_name(kind),
        " interface");
  return plugin;
}

// A subcommand: `run` receives the arguments after the command name, common options removed,
// and returns the process exit code. Errors are thrown (facetool::Error, UsageError, or
// boost::program_options errors) and reported by main().
struct Command {
  std::string name;
  std::string summary;  // one line for `facetool --help`
  std::function<int(CommandContext& context, const std::vector<std::string>& args)> run;
};

// Adds a command to the registry during static initialisation. Each commands/<name>_command.cpp
// defines one: `const CommandRegistration registration{{"name", "summary", run_name}};`
struct CommandRegistration {
  explicit CommandRegistration(Command command);
};

// Every registered command, sorted by name.
const std::vector<Command>& all_commands();
// The command called `name`; throws UsageError listing the known commands if there is none.
const Command& find_command(const std::string& name);

}  // namespace facetool
