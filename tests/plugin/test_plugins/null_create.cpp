// A plugin whose create function fails (returns null); it loads, but creating it must throw.
#include "core/plugin/plugin_api.h"

namespace {

void* create_nothing() { return nullptr; }
void destroy_nothing(void*) {}

const facetool_plugin_descriptor kDescriptor = {
    FACETOOL_PLUGIN_API_VERSION, "null_create",  "1.0.0", FACETOOL_PLUGIN_RENDERER,
    "a plugin whose create fails", create_nothing, destroy_nothing,
    FACETOOL_PLUGIN_CXX_ABI, FACETOOL_PLUGIN_COMPILER};

}  // namespace

extern "C" __attribute__((visibility("default"))) const facetool_plugin_descriptor*
facetool_plugin_entry(void) {
  return &kDescriptor;
}
