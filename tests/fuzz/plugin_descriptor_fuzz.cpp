// libFuzzer target: the checks the plugin loader applies to a descriptor after dlopen, fed
// descriptors built from fuzz bytes; what passes must be exactly what the ABI promises.
// Input: byte 0 holds flags (bit 0: a wrong API version taken from bytes 2..5; bits 1..3: null
// name/version/description; bits 4..5: null create/destroy; bit 6: another C++ ABI; bit 7: no
// compiler), byte 1 the kind, and the bytes after the header are split at '\0' into name, version
// and description.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "core/plugin/plugin_descriptor.h"
#include "core/util/error.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

void* create_nothing() { return nullptr; }
void destroy_nothing(void*) {}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 6) return 0;
  const uint8_t flags = data[0];
  facetool_plugin_descriptor d{};
  d.api_version = FACETOOL_PLUGIN_API_VERSION;
  if (flags & 1) std::memcpy(&d.api_version, data + 2, 4);
  d.kind = data[1];
  std::vector<std::string> texts(3);
  size_t part = 0;
  for (size_t k = 6; k < size && part < texts.size(); ++k) {
    if (data[k] == 0) ++part;
    else texts[part] += static_cast<char>(data[k]);
  }
  d.name = (flags & 2) ? nullptr : texts[0].c_str();
  d.version = (flags & 4) ? nullptr : texts[1].c_str();
  d.description = (flags & 8) ? nullptr : texts[2].c_str();
  d.create = (flags & 16) ? nullptr : create_nothing;
  d.destroy = (flags & 32) ? nullptr : destroy_nothing;
  d.cxx_abi = (flags & 64) ? "libc++-of-another-world" : FACETOOL_PLUGIN_CXX_ABI;
  d.compiler = (flags & 128) ? nullptr : FACETOOL_PLUGIN_COMPILER;

  using facetool::fuzz::require;
  try {
    const facetool::PluginInfo info = facetool::validate_plugin_descriptor(&d, "fuzz.ftplugin.so");
    require(d.api_version == FACETOOL_PLUGIN_API_VERSION, "accepted another API version");
    require(d.name != nullptr && !info.name.empty() && info.name == d.name, "name not kept");
    require(info.kind == FACETOOL_PLUGIN_NETWORK || info.kind == FACETOOL_PLUGIN_LOSS ||
                info.kind == FACETOOL_PLUGIN_RENDERER,
            "accepted an unknown kind");
    require(d.create != nullptr && d.destroy != nullptr, "accepted missing create/destroy");
    require(!(flags & 64), "accepted another C++ ABI");
    require(info.version == (d.version ? d.version : "") &&
                info.description == (d.description ? d.description : ""),
            "version or description not kept");
    require(info.descriptor == &d && info.path == "fuzz.ftplugin.so", "descriptor or path not kept");
  } catch (const facetool::Error&) {
  }
  try {
    facetool::validate_plugin_descriptor(nullptr, "fuzz.ftplugin.so");
    require(false, "accepted a null descriptor");
  } catch (const facetool::Error&) {
  }
  return 0;
}
