// A plugin built for a newer plugin API (FACETOOL_PLUGIN_API_VERSION + 1): must be refused.
#include "core/plugin/plugin_api.h"

namespace {

void* create_nothing() { return nullptr; }
void destroy_nothing(void*) {}

const facetool_plugin_descriptor kDescriptor = {
    FACETOOL_PLUGIN_API_VERSION + 1, "wrong_version", "1.0.0", FACETOOL_PLUGIN_LOSS,
    "a plugin built for another API version", create_nothing, destroy_nothing};

}  // namespace

extern "C" __attribute__((visibility("default"))) const facetool_plugin_descriptor*
facetool_plugin_entry(void) {
  return &kDescriptor;
}
