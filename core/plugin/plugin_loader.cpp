// Plugin loader: opens plugin libraries, validates their descriptors, creates plugin objects.
#include "core/plugin/plugin_loader.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "core/plugin/plugin_descriptor.h"
#include "core/util/error.h"
#include "core/util/shared_library.h"

namespace facetool {
namespace {

// The path used to recognise a file that was already loaded: absolute and normalised.
std::string normalized_path(const std::string& path) {
  std::error_code ec;
  std::filesystem::path canonical = std::filesystem::weakly_canonical(path, ec);
  if (ec) return std::filesystem::absolute(path, ec).lexically_normal().string();
  return canonical.string();
}

// Reads and validates the descriptor exported by the library at `path`.
PluginInfo read_descriptor(const std::string& path) {
  std::error_code ec;
  check(std::filesystem::exists(path, ec), "plugin file '", path,
        "' does not exist; check the path given to --plugin or FACETOOL_PLUGIN_PATH");
  check(std::filesystem::is_regular_file(path, ec), "plugin file '", path,
        "' is not a regular file; give the path of a ", FACETOOL_PLUGIN_FILE_SUFFIX, " library");

  SharedLibrary library = [&] {
    try {
      return SharedLibrary::open(path);
    } catch (const Error& e) {
      fail("plugin file '", path, "' is not a loadable library (", e.what(),
           "); rebuild it as a shared library for this platform");
    }
  }();

  auto entry = reinterpret_cast<facetool_plugin_entry_fn>(
      library.symbol(FACETOOL_PLUGIN_ENTRY_SYMBOL));
  check(entry != nullptr, "plugin file '", path, "' does not export the entry point '",
        FACETOOL_PLUGIN_ENTRY_SYMBOL, "'; define it with FACETOOL_DEFINE_PLUGIN (see ",
        "core/plugin/plugin_api.h)");

  return validate_plugin_descriptor(entry(), path);
}

}  // namespace

const char* plugin_kind_name(uint32_t kind) {
  switch (kind) {
    case FACETOOL_PLUGIN_NETWORK:
      return "network";
    case FACETOOL_PLUGIN_LOSS:
      return "loss";
    case FACETOOL_PLUGIN_RENDERER:
      return "renderer";
    default:
      return "unknown";
  }
}

std::vector<std::string> PluginLoader::default_search_dirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("FACETOOL_PLUGIN_PATH"))
    for (const std::string& dir : split_path_list(env)) dirs.push_back(dir);
  const std::string exe = executable_dir();
  if (!exe.empty()) {
    dirs.push_back(exe);
    dirs.push_back(exe + "/../lib/facetool/plugins");
  }
  return dirs;
}

PluginLoader::PluginLoader() : dirs_(default_search_dirs()) {}

void PluginLoader::set_search_dirs(std::vector<std::string> dirs) { dirs_ = std::move(dirs); }

const PluginInfo& PluginLoader::load_file(const std::string& path) {
  const std::string key = normalized_path(path);
  for (const PluginInfo& loaded : plugins_)
    if (normalized_path(loaded.path) == key) return loaded;

  PluginInfo info = read_descriptor(path);
  for (const PluginInfo& loaded : plugins_)
    check(loaded.name != info.name, "plugin name '", info.name, "' from ", path,
          " is already provided by ", loaded.path,
          "; remove one of the two files or rename one plugin");
  plugins_.push_back(std::move(info));
  return plugins_.back();
}

void PluginLoader::discover() {
  for (const std::string& dir : dirs_) {
    for (const std::string& file : files_with_suffix(dir, FACETOOL_PLUGIN_FILE_SUFFIX)) {
      try {
        load_file(file);
      } catch (const Error& e) {
        // The same broken file may sit on the path twice or be rediscovered; report it once.
        bool known = false;
        for (const std::string& problem : problems_) known = known || problem == e.what();
        if (!known) problems_.push_back(e.what());
      }
    }
  }
}

const PluginInfo& PluginLoader::find(uint32_t kind, const std::string& name) const {
  std::string available;
  for (const PluginInfo& info : plugins_) {
    if (info.kind != kind) continue;
    if (info.name == name) return info;
    available += (available.empty() ? "" : ", ") + info.name;
  }
  fail("no ", plugin_kind_name(kind), " plugin called '", name, "' is loaded; available ",
       plugin_kind_name(kind), " plugins: ", available.empty() ? "none" : available,
       " (run 'facetool plugins' to see the search path, or load one with --plugin FILE)");
}

std::shared_ptr<Plugin> PluginLoader::create(const PluginInfo& info) const {
  check(info.descriptor != nullptr, "plugin '", info.name,
        "' has no descriptor; obtain plugins from PluginLoader::load_file or discover");
  const facetool_plugin_descriptor* descriptor = info.descriptor;
  void* object = descriptor->create();
  check(object != nullptr, "plugin '", info.name, "' from ", info.path,
        " failed to create its object; check the plugin's requirements or rebuild it");
  return std::shared_ptr<Plugin>(static_cast<Plugin*>(object),
                                 [descriptor](Plugin* p) { descriptor->destroy(p); });
}

}  // namespace facetool
