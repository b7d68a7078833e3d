// The plugin ABI: the one extern "C" entry point every facetool plugin library exports.
#pragma once

#include <cstdint>

// Bumped whenever this descriptor or any plugin interface class (core/plugin/*_plugin.h)
// changes; the loader refuses a plugin built for another version. History: docs/plugins.md.
#define FACETOOL_PLUGIN_API_VERSION 2

extern "C" {

enum facetool_plugin_kind : uint32_t {
  FACETOOL_PLUGIN_NETWORK = 1,
  FACETOOL_PLUGIN_LOSS = 2,
  FACETOOL_PLUGIN_RENDERER = 3,
};

struct facetool_plugin_descriptor {
  uint32_t api_version;     // FACETOOL_PLUGIN_API_VERSION the plugin was built with
  const char* name;         // unique among loaded plugins, e.g. "sh_renderer"
  const char* version;      // the plugin's own version, e.g. "1.0.0"
  uint32_t kind;            // a facetool_plugin_kind
  const char* description;  // one line for `facetool plugins`
  // Creates the plugin object: a facetool::Plugin subclass matching `kind`. Must not throw;
  // returns nullptr on failure.
  void* (*create)(void);
  // Destroys an object returned by create.
  void (*destroy)(void* object);
};

typedef const facetool_plugin_descriptor* (*facetool_plugin_entry_fn)(void);
}

#define FACETOOL_PLUGIN_ENTRY_SYMBOL "facetool_plugin_entry"
// Plugin files are named <name>.ftplugin.so; the loader picks up every such file on its path.
#define FACETOOL_PLUGIN_FILE_SUFFIX ".ftplugin.so"

// Defines the entry point of a plugin whose object is `Class` (default-constructible).
#define FACETOOL_DEFINE_PLUGIN(Class, kind_, name_, version_, description_)                   \
  extern "C" __attribute__((visibility("default"))) const facetool_plugin_descriptor*         \
  facetool_plugin_entry(void) {                                                               \
    static const facetool_plugin_descriptor descriptor = {                                    \
        FACETOOL_PLUGIN_API_VERSION, name_, version_, kind_, description_,                    \
        []() -> void* {                                                                       \
          try {                                                                               \
            return static_cast<facetool::Plugin*>(new Class());                               \
          } catch (...) {                                                                     \
            return nullptr;                                                                   \
          }                                                                                   \
        },                                                                                    \
        [](void* object) { delete static_cast<facetool::Plugin*>(object); }};                 \
    return &descriptor;                                                                       \
  }
