// The entry point a run-time loadable backend module (e.g. opencl) exports.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/backend/backend.h"

// Bumped whenever Backend or BackendModule changes; modules must match exactly because they are
// built together with facetool.
#define FACETOOL_BACKEND_MODULE_API_VERSION 2

namespace facetool {

class BackendModule {
 public:
  virtual ~BackendModule() = default;
  virtual std::string name() const = 0;
  // One line per device ("0: pthread-skylake-avx512 (Portable Computing Language)"). Throws
  // facetool::Error explaining why when the runtime is missing or has no device.
  virtual std::vector<std::string> devices() = 0;
  // Creates a backend on the device chosen by `device` (empty: the default device; an index;
  // or part of a device name). Throws facetool::Error on failure.
  virtual std::unique_ptr<Backend> create(const std::string& device) = 0;
};

}  // namespace facetool

extern "C" {
struct facetool_backend_module_descriptor {
  uint32_t api_version;  // FACETOOL_BACKEND_MODULE_API_VERSION
  const char* name;
  facetool::BackendModule* (*create_module)();  // never returns null; throws nothing
};
// Every backend module exports this symbol.
typedef const facetool_backend_module_descriptor* (*facetool_backend_module_entry_fn)();
}
#define FACETOOL_BACKEND_MODULE_ENTRY_SYMBOL "facetool_backend_module_entry"
