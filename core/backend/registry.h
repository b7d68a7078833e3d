// Backend registry: finds backends by name at run time ("cpu", "opencl", "opencl:1").
#pragma once

#include <string>
#include <vector>

#include "core/backend/backend.h"

namespace facetool {

struct BackendInfo {
  std::string name;                  // "cpu", "opencl"
  bool available = false;
  std::string reason;                // why it is unavailable, and what to do
  std::vector<std::string> devices;  // one line per device, "index: description"
};

// Returns the backend for `spec`: a name optionally followed by ':' and a device index or a
// case-insensitive part of the device name ("opencl:0", "opencl:pthread"). Backends are created
// once per spec and live until the process ends. Throws facetool::Error if the backend is
// unknown or unavailable, with the reason.
Backend& get_backend(const std::string& spec = "cpu");

// Every backend facetool knows of, whether it can run here, and its devices.
std::vector<BackendInfo> list_backends();

// Names of the backends that can run on this machine (always includes "cpu").
std::vector<std::string> available_backends();

}  // namespace facetool
