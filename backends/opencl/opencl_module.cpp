// Entry point of facetool_backend_opencl.so: lists OpenCL devices and creates backends on them.
#include <memory>
#include <string>
#include <vector>

#include "backends/opencl/opencl_backend.h"
#include "backends/opencl/opencl_context.h"
#include "core/backend/backend_module.h"

namespace facetool::opencl {
namespace {

class OpenclModule : public BackendModule {
 public:
  std::string name() const override { return "opencl"; }

  std::vector<std::string> devices() override {
    std::vector<std::string> lines;
    const std::vector<DeviceEntry> entries = enumerate_devices();
    for (size_t i = 0; i < entries.size(); ++i)
      lines.push_back(std::to_string(i) + ": " + entries[i].describe());
    return lines;
  }

  std::unique_ptr<Backend> create(const std::string& device) override {
    return std::make_unique<OpenclBackend>(select_device(device));
  }
};

BackendModule* create_module() { return new OpenclModule(); }

}  // namespace
}  // namespace facetool::opencl

extern "C" __attribute__((visibility("default"))) const facetool_backend_module_descriptor*
facetool_backend_module_entry() {
  static const facetool_backend_module_descriptor descriptor = {
      FACETOOL_BACKEND_MODULE_API_VERSION, "opencl", &facetool::opencl::create_module};
  return &descriptor;
}
