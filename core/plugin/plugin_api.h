// The plugin ABI: the one extern "C" entry point every facetool plugin library exports.
#pragma once

#include <cstdint>  // also defines the standard library's ABI macros used below

// Bumped whenever this descriptor or any plugin interface class (core/plugin/*_plugin.h)
// changes; the loader refuses a plugin built for another version. History: docs/plugins.md.
#define FACETOOL_PLUGIN_API_VERSION 7

// The C++ ABI a plugin object crosses the library boundary with: the standard library and, for
// libstdc++, its std::string/std::list ABI (_GLIBCXX_USE_CXX11_ABI). A plugin compiled for another
// one is refused (docs/plugins.md, "ABI policy"). Compilers that share these (gcc and clang with
// libstdc++) interoperate. A build may define it to test the refusal; never to hide a mismatch.
#ifndef FACETOOL_PLUGIN_CXX_ABI
#if defined(_LIBCPP_VERSION)
#define FACETOOL_PLUGIN_CXX_ABI "libc++"
#elif defined(__GLIBCXX__) && defined(_GLIBCXX_USE_CXX11_ABI) && _GLIBCXX_USE_CXX11_ABI
#define FACETOOL_PLUGIN_CXX_ABI "libstdc++/cxx11"
#elif defined(__GLIBCXX__)
#define FACETOOL_PLUGIN_CXX_ABI "libstdc++/cxx98"
#else
#define FACETOOL_PLUGIN_CXX_ABI "unknown"
#endif
#endif

// The compiler a plugin was built with, shown by `facetool plugins` and in refusals.
#ifndef FACETOOL_PLUGIN_COMPILER
#if defined(__clang__)
#define FACETOOL_PLUGIN_COMPILER "clang " __clang_version__
#elif defined(__GNUC__)
#define FACETOOL_PLUGIN_COMPILER "gcc " __VERSION__
#else
#define FACETOOL_PLUGIN_COMPILER "unknown compiler"
#endif
#endif

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
  // Since version 3: FACETOOL_PLUGIN_CXX_ABI and FACETOOL_PLUGIN_COMPILER of the plugin's build.
  const char* cxx_abi;
  const char* compiler;
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
        [](void* object) { delete static_cast<facetool::Plugin*>(object); },                  \
        FACETOOL_PLUGIN_CXX_ABI, FACETOOL_PLUGIN_COMPILER};                                   \
    return &descriptor;                                                                       \
  }
