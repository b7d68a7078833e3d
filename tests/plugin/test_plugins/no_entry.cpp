// A shared library that does not export facetool_plugin_entry: must be refused.
extern "C" __attribute__((visibility("default"))) int not_a_plugin_entry(void) { return 0; }
