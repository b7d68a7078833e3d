// A plugin declaring a kind facetool does not know (99): must be refused.
#include "core/plugin/plugin_api.h"

namespace {

void* create_nothing() { return nullptr; }
void destroy_nothing(void*) {}

const facetool_plugin_descriptor kDescriptor = {
    FACETOOL_PLUGIN_API_VERSION, "unknown_kind", "1.0.0", 99u,
    "a plugin of an unknown kind", create_nothing, destroy_nothing,
    FACETOOL_PLUGIN_CXX_ABI, FACETOOL_PLUGIN_COMPILER};

}  // namespace

extern "C" __attribute__((visibility("default"))) const facetool_plugin_descriptor*
facetool_plugin_entry(void) {
  return &kDescriptor;
}
