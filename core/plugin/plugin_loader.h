// Plugin loader: finds plugin libraries on a search path, checks their descriptors, creates them.
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "core/plugin/plugin.h"
#include "core/plugin/plugin_api.h"

namespace facetool {

const char* plugin_kind_name(uint32_t kind);  // "network", "loss", "renderer", "unknown"

struct PluginInfo {
  std::string path;
  std::string name;
  std::string version;
  uint32_t kind = 0;
  std::string description;
  std::string compiler;  // the compiler the plugin was built with (FACETOOL_PLUGIN_COMPILER)
  const facetool_plugin_descriptor* descriptor = nullptr;
};

class PluginLoader {
 public:
  // Folders searched by discover(), in order: each entry of FACETOOL_PLUGIN_PATH, the folder
  // beside the executable, and <executable>/../lib/facetool/plugins.
  static std::vector<std::string> default_search_dirs();

  PluginLoader();  // starts with default_search_dirs()
  void set_search_dirs(std::vector<std::string> dirs);
  const std::vector<std::string>& search_dirs() const { return dirs_; }

  // Loads one plugin file (an explicit --plugin FILE). Throws facetool::Error naming the file
  // for a missing file, a missing entry point, a mismatched API version (both versions in the
  // message), an unknown kind, or a name already loaded from another file.
  const PluginInfo& load_file(const std::string& path);
  // Loads every *.ftplugin.so on the search dirs. Files that fail are skipped and their errors
  // kept in problems(); a file already loaded (same path) is skipped silently.
  void discover();

  const std::deque<PluginInfo>& plugins() const { return plugins_; }
  const std::vector<std::string>& problems() const { return problems_; }
  // The plugin of `kind` called `name`; throws listing the available ones if none matches.
  const PluginInfo& find(uint32_t kind, const std::string& name) const;
  // Creates the plugin's object; throws if its create function fails.
  std::shared_ptr<Plugin> create(const PluginInfo& info) const;

 private:
  std::vector<std::string> dirs_;
  std::deque<PluginInfo> plugins_;  // a deque: references handed out stay valid
  std::vector<std::string> problems_;
};

}  // namespace facetool
