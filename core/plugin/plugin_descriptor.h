// Validation of a plugin's descriptor (what the loader checks once the library is open).
#pragma once

#include <string>

#include "core/plugin/plugin_api.h"
#include "core/plugin/plugin_loader.h"

namespace facetool {

// Checks the descriptor a plugin library at `path` returned from its entry point and returns
// its PluginInfo. Throws facetool::Error naming `path` for a null descriptor, a mismatched API
// version (both versions in the message), another C++ ABI (both ABIs and compilers), a missing
// name, an unknown kind, or missing create/destroy functions. Reads only the fields; never calls the plugin's functions.
PluginInfo validate_plugin_descriptor(const facetool_plugin_descriptor* descriptor,
                                      const std::string& path);

}  // namespace facetool
