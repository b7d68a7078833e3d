// Plugin: the base class of every plugin object; each kind adds its own interface on top.
#pragma once

namespace facetool {

// Objects created by a plugin's entry point derive from this. Kind-specific interfaces
// (network, loss, renderer) derive from it in core/plugin/<kind>_plugin.h.
class Plugin {
 public:
  // Defined in the core library, so every plugin shares one type_info for dynamic_cast.
  virtual ~Plugin();
};

}  // namespace facetool
