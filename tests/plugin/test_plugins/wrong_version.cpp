// A plugin built for another plugin API: FACETOOL_TEST_API_VERSION (default: the next version;
// tests/plugin builds it a second time as old_version with the previous one). Must be refused.
#include "core/plugin/plugin_api.h"

#ifndef FACETOOL_TEST_API_VERSION
#define FACETOOL_TEST_API_VERSION (FACETOOL_PLUGIN_API_VERSION + 1)
#endif

namespace {

void* create_nothing() { return nullptr; }
void destroy_nothing(void*) {}

// Only api_version is read from a descriptor of another version, so its layout may differ.
const facetool_plugin_descriptor kDescriptor = {
    FACETOOL_TEST_API_VERSION, "wrong_version", "1.0.0", FACETOOL_PLUGIN_LOSS,
    "a plugin built for another API version", create_nothing, destroy_nothing,
    FACETOOL_PLUGIN_CXX_ABI, FACETOOL_PLUGIN_COMPILER};

}  // namespace

extern "C" __attribute__((visibility("default"))) const facetool_plugin_descriptor*
facetool_plugin_entry(void) {
  return &kDescriptor;
}
