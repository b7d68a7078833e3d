// Plugin descriptor validation, separate from dlopen so that it can be tested and fuzzed alone.
#include "core/plugin/plugin_descriptor.h"

#include "core/util/error.h"

namespace facetool {
namespace {

std::string text_or_empty(const char* text) { return text ? std::string(text) : std::string(); }

bool is_known_kind(uint32_t kind) {
  return kind == FACETOOL_PLUGIN_NETWORK || kind == FACETOOL_PLUGIN_LOSS ||
         kind == FACETOOL_PLUGIN_RENDERER;
}

}  // namespace

PluginInfo validate_plugin_descriptor(const facetool_plugin_descriptor* descriptor,
                                      const std::string& path) {
  check(descriptor != nullptr, "plugin file '", path, "': ", FACETOOL_PLUGIN_ENTRY_SYMBOL,
        " returned no descriptor; the plugin is broken, rebuild it with FACETOOL_DEFINE_PLUGIN");
  // api_version is the first field in every version of the ABI, so it is safe to read before
  // anything else; the rest of the layout is only trusted once the version matches.
  check(descriptor->api_version == FACETOOL_PLUGIN_API_VERSION, path,
        " was built for facetool plugin API version ", descriptor->api_version,
        ", but this facetool uses version ", FACETOOL_PLUGIN_API_VERSION,
        "; rebuild the plugin against this facetool's SDK");
  // Same layout from here on: the C++ ABI must match before any object crosses the boundary.
  const std::string cxx_abi = text_or_empty(descriptor->cxx_abi);
  check(cxx_abi == FACETOOL_PLUGIN_CXX_ABI, path, " was built for the C++ ABI '",
        cxx_abi.empty() ? "unrecorded" : cxx_abi, "' (", text_or_empty(descriptor->compiler),
        "), but this facetool uses '", FACETOOL_PLUGIN_CXX_ABI, "' (", FACETOOL_PLUGIN_COMPILER,
        "); rebuild the plugin with a compiler and standard library of that ABI");

  const std::string name = text_or_empty(descriptor->name);
  check(!name.empty(), "plugin file '", path,
        "' has a descriptor without a name; give the plugin a name in FACETOOL_DEFINE_PLUGIN");
  check(is_known_kind(descriptor->kind), "plugin '", name, "' from ", path,
        " declares unknown kind ", descriptor->kind,
        "; use FACETOOL_PLUGIN_NETWORK, FACETOOL_PLUGIN_LOSS or FACETOOL_PLUGIN_RENDERER");
  check(descriptor->create != nullptr && descriptor->destroy != nullptr, "plugin '", name,
        "' from ", path, " has no create/destroy functions in its descriptor; ",
        "define it with FACETOOL_DEFINE_PLUGIN");

  PluginInfo info;
  info.path = path;
  info.name = name;
  info.version = text_or_empty(descriptor->version);
  info.kind = descriptor->kind;
  info.description = text_or_empty(descriptor->description);
  info.compiler = text_or_empty(descriptor->compiler);
  info.descriptor = descriptor;
  return info;
}

}  // namespace facetool
