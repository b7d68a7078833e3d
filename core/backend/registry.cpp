// Backend registry: the built-in cpu backend plus modules loaded at run time (opencl).
#include "core/backend/registry.h"

#include <map>
#include <memory>
#include <mutex>

#include "backends/cpu/cpu_backend.h"
#include "core/backend/backend_module.h"
#include "core/util/error.h"
#include "core/util/shared_library.h"

namespace facetool {
namespace {

// Backend modules facetool knows how to load, by name; each is facetool_backend_<name>.so.
const std::vector<std::string> kModuleNames = {"opencl"};

struct ModuleSlot {
  std::unique_ptr<BackendModule> module;  // null when unavailable
  std::string reason;
};

struct Registry {
  std::mutex mutex;
  std::map<std::string, std::unique_ptr<Backend>> backends;  // by full spec
  std::map<std::string, ModuleSlot> modules;                  // by module name
};

Registry& registry() {
  static Registry* r = new Registry();  // never destroyed: backends outlive static tensors
  return *r;
}

ModuleSlot load_module(const std::string& name) {
  ModuleSlot slot;
  const std::string file = "facetool_backend_" + name + ".so";
  const std::string path = find_module_file(file, "FACETOOL_BACKEND_PATH", slot.reason);
  if (path.empty()) return slot;
  try {
    SharedLibrary lib = SharedLibrary::open(path);
    auto entry = reinterpret_cast<facetool_backend_module_entry_fn>(
        lib.symbol(FACETOOL_BACKEND_MODULE_ENTRY_SYMBOL));
    if (!entry) {
      slot.reason = path + " does not export " FACETOOL_BACKEND_MODULE_ENTRY_SYMBOL;
      return slot;
    }
    const facetool_backend_module_descriptor* d = entry();
    if (d->api_version != FACETOOL_BACKEND_MODULE_API_VERSION) {
      slot.reason = path + " was built for backend API version " +
                    std::to_string(d->api_version) + " but facetool uses version " +
                    std::to_string(FACETOOL_BACKEND_MODULE_API_VERSION) +
                    "; rebuild it with this facetool";
      return slot;
    }
    slot.module.reset(d->create_module());
    return slot;
  } catch (const Error& e) {
    slot.reason = std::string(e.what()) +
                  " (is the OpenCL ICD loader installed? apt-get install ocl-icd-libopencl1)";
    return slot;
  }
}

ModuleSlot& module_slot(const std::string& name) {
  Registry& r = registry();
  auto it = r.modules.find(name);
  if (it == r.modules.end()) it = r.modules.emplace(name, load_module(name)).first;
  return it->second;
}

bool is_module_name(const std::string& name) {
  for (const auto& m : kModuleNames)
    if (m == name) return true;
  return false;
}

}  // namespace

Backend& get_backend(const std::string& spec) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  auto found = r.backends.find(spec);
  if (found != r.backends.end()) return *found->second;

  const size_t colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const std::string device = colon == std::string::npos ? "" : spec.substr(colon + 1);
  std::unique_ptr<Backend> backend;
  if (name == "cpu") {
    check(device.empty() || device == "0", "backend 'cpu' has one device (0), not '", device, "'");
    backend = make_cpu_backend();
  } else if (is_module_name(name)) {
    ModuleSlot& slot = module_slot(name);
    check(slot.module != nullptr, "backend '", name, "' is unavailable: ", slot.reason);
    backend = slot.module->create(device);
  } else {
    std::string known = "cpu";
    for (const auto& m : kModuleNames) known += ", " + m;
    fail("unknown backend '", name, "'; known backends: ", known,
         " (run 'facetool backends' to see which can run here)");
  }
  Backend& ref = *backend;
  r.backends.emplace(spec, std::move(backend));
  return ref;
}

std::vector<BackendInfo> list_backends() {
  std::vector<BackendInfo> infos;
  BackendInfo cpu;
  cpu.name = "cpu";
  cpu.available = true;
  cpu.devices.push_back("0: " + get_backend("cpu").device_description());
  infos.push_back(cpu);
  Registry& r = registry();
  for (const std::string& name : kModuleNames) {
    BackendInfo info;
    info.name = name;
    std::lock_guard<std::mutex> lock(r.mutex);
    ModuleSlot& slot = module_slot(name);
    if (!slot.module) {
      info.reason = slot.reason;
    } else {
      try {
        info.devices = slot.module->devices();
        info.available = !info.devices.empty();
        if (!info.available) info.reason = "no devices";
      } catch (const Error& e) {
        info.reason = e.what();
      }
    }
    infos.push_back(info);
  }
  return infos;
}

std::vector<std::string> available_backends() {
  std::vector<std::string> names;
  for (const BackendInfo& info : list_backends())
    if (info.available) names.push_back(info.name);
  return names;
}

}  // namespace facetool
