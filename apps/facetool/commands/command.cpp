// The command registry and the lazily created plugin loader of CommandContext.
#include "apps/facetool/commands/command.h"

#include <algorithm>
#include <iostream>

namespace facetool {
namespace {

std::vector<Command>& registry() {
  static std::vector<Command> commands;
  return commands;
}

}  // namespace

CommandRegistration::CommandRegistration(Command command) {
  std::vector<Command>& commands = registry();
  commands.push_back(std::move(command));
  std::sort(commands.begin(), commands.end(),
            [](const Command& a, const Command& b) { return a.name < b.name; });
}

const std::vector<Command>& all_commands() { return registry(); }

const Command& find_command(const std::string& name) {
  std::string known;
  for (const Command& command : all_commands()) {
    if (command.name == name) return command;
    known += (known.empty() ? "" : ", ") + command.name;
  }
  throw UsageError("unknown command '" + name + "'; commands: " + known);
}

PluginLoader& CommandContext::plugins() {
  if (!plugins_) {
    auto loader = std::make_unique<PluginLoader>();
    for (const std::string& file : plugin_files) loader->load_file(file);
    loader->discover();
    if (verbose)
      for (const std::string& problem : loader->problems())
        std::cerr << "facetool: warning: skipped plugin: " << problem << '\n';
    plugins_ = std::move(loader);
  }
  return *plugins_;
}

}  // namespace facetool
