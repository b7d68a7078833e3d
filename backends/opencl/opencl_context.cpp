// OpenCL device discovery, context/queue creation and the error-code helpers.
#include "backends/opencl/opencl_context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <sstream>

#include "core/util/error.h"

namespace facetool::opencl {

std::string error_string(cl_int code) {
  const char* name = "unknown OpenCL error";
  switch (code) {
#define FACETOOL_CL_CASE(c) \
  case c:                   \
    name = #c;              \
    break;
    FACETOOL_CL_CASE(CL_SUCCESS)
    FACETOOL_CL_CASE(CL_DEVICE_NOT_FOUND)
    FACETOOL_CL_CASE(CL_DEVICE_NOT_AVAILABLE)
    FACETOOL_CL_CASE(CL_COMPILER_NOT_AVAILABLE)
    FACETOOL_CL_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    FACETOOL_CL_CASE(CL_OUT_OF_RESOURCES)
    FACETOOL_CL_CASE(CL_OUT_OF_HOST_MEMORY)
    FACETOOL_CL_CASE(CL_PROFILING_INFO_NOT_AVAILABLE)
    FACETOOL_CL_CASE(CL_MEM_COPY_OVERLAP)
    FACETOOL_CL_CASE(CL_IMAGE_FORMAT_MISMATCH)
    FACETOOL_CL_CASE(CL_IMAGE_FORMAT_NOT_SUPPORTED)
    FACETOOL_CL_CASE(CL_BUILD_PROGRAM_FAILURE)
    FACETOOL_CL_CASE(CL_MAP_FAILURE)
    FACETOOL_CL_CASE(CL_MISALIGNED_SUB_BUFFER_OFFSET)
    FACETOOL_CL_CASE(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
    FACETOOL_CL_CASE(CL_COMPILE_PROGRAM_FAILURE)
    FACETOOL_CL_CASE(CL_LINKER_NOT_AVAILABLE)
    FACETOOL_CL_CASE(CL_LINK_PROGRAM_FAILURE)
    FACETOOL_CL_CASE(CL_DEVICE_PARTITION_FAILED)
    FACETOOL_CL_CASE(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
    FACETOOL_CL_CASE(CL_INVALID_VALUE)
    FACETOOL_CL_CASE(CL_INVALID_DEVICE_TYPE)
    FACETOOL_CL_CASE(CL_INVALID_PLATFORM)
    FACETOOL_CL_CASE(CL_INVALID_DEVICE)
    FACETOOL_CL_CASE(CL_INVALID_CONTEXT)
    FACETOOL_CL_CASE(CL_INVALID_QUEUE_PROPERTIES)
    FACETOOL_CL_CASE(CL_INVALID_COMMAND_QUEUE)
    FACETOOL_CL_CASE(CL_INVALID_HOST_PTR)
    FACETOOL_CL_CASE(CL_INVALID_MEM_OBJECT)
    FACETOOL_CL_CASE(CL_INVALID_IMAGE_FORMAT_DESCRIPTOR)
    FACETOOL_CL_CASE(CL_INVALID_IMAGE_SIZE)
    FACETOOL_CL_CASE(CL_INVALID_SAMPLER)
    FACETOOL_CL_CASE(CL_INVALID_BINARY)
    FACETOOL_CL_CASE(CL_INVALID_BUILD_OPTIONS)
    FACETOOL_CL_CASE(CL_INVALID_PROGRAM)
    FACETOOL_CL_CASE(CL_INVALID_PROGRAM_EXECUTABLE)
    FACETOOL_CL_CASE(CL_INVALID_KERNEL_NAME)
    FACETOOL_CL_CASE(CL_INVALID_KERNEL_DEFINITION)
    FACETOOL_CL_CASE(CL_INVALID_KERNEL)
    FACETOOL_CL_CASE(CL_INVALID_ARG_INDEX)
    FACETOOL_CL_CASE(CL_INVALID_ARG_VALUE)
    FACETOOL_CL_CASE(CL_INVALID_ARG_SIZE)
    FACETOOL_CL_CASE(CL_INVALID_KERNEL_ARGS)
    FACETOOL_CL_CASE(CL_INVALID_WORK_DIMENSION)
    FACETOOL_CL_CASE(CL_INVALID_WORK_GROUP_SIZE)
    FACETOOL_CL_CASE(CL_INVALID_WORK_ITEM_SIZE)
    FACETOOL_CL_CASE(CL_INVALID_GLOBAL_OFFSET)
    FACETOOL_CL_CASE(CL_INVALID_EVENT_WAIT_LIST)
    FACETOOL_CL_CASE(CL_INVALID_EVENT)
    FACETOOL_CL_CASE(CL_INVALID_OPERATION)
    FACETOOL_CL_CASE(CL_INVALID_GL_OBJECT)
    FACETOOL_CL_CASE(CL_INVALID_BUFFER_SIZE)
    FACETOOL_CL_CASE(CL_INVALID_MIP_LEVEL)
    FACETOOL_CL_CASE(CL_INVALID_GLOBAL_WORK_SIZE)
    FACETOOL_CL_CASE(CL_INVALID_PROPERTY)
    FACETOOL_CL_CASE(CL_INVALID_IMAGE_DESCRIPTOR)
    FACETOOL_CL_CASE(CL_INVALID_COMPILER_OPTIONS)
    FACETOOL_CL_CASE(CL_INVALID_LINKER_OPTIONS)
    FACETOOL_CL_CASE(CL_INVALID_DEVICE_PARTITION_COUNT)
#undef FACETOOL_CL_CASE
    case -1001:
      name = "CL_PLATFORM_NOT_FOUND_KHR";
      break;
    default:
      break;
  }
  return std::string(name) + " (" + std::to_string(code) + ")";
}

void check_cl(cl_int code, const char* what) {
  if (code != CL_SUCCESS) fail("OpenCL: ", what, " failed: ", error_string(code));
}

std::string device_string(cl_device_id device, cl_device_info info) {
  size_t size = 0;
  check_cl(clGetDeviceInfo(device, info, 0, nullptr, &size), "clGetDeviceInfo");
  std::string s(size, '\0');
  check_cl(clGetDeviceInfo(device, info, size, s.data(), nullptr), "clGetDeviceInfo");
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::string platform_string(cl_platform_id platform, cl_platform_info info) {
  size_t size = 0;
  check_cl(clGetPlatformInfo(platform, info, 0, nullptr, &size), "clGetPlatformInfo");
  std::string s(size, '\0');
  check_cl(clGetPlatformInfo(platform, info, size, s.data(), nullptr), "clGetPlatformInfo");
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::string DeviceEntry::describe() const {
  char memory[32];
  std::snprintf(memory, sizeof memory, "%.1f GiB", double(global_memory) / (1024.0 * 1024 * 1024));
  std::ostringstream out;
  out << name << " (" << platform_name << "), " << compute_units << " compute units, " << memory;
  return out.str();
}

static const char* kNoPlatformAdvice =
    "install an ICD such as pocl-opencl-icd (CPU) or your GPU vendor's";

std::vector<DeviceEntry> enumerate_devices() {
  cl_uint platform_count = 0;
  cl_int status = clGetPlatformIDs(0, nullptr, &platform_count);
  if (status == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || platform_count == 0)
    fail("no OpenCL platform found: ", kNoPlatformAdvice);
  check_cl(status, "clGetPlatformIDs");
  std::vector<cl_platform_id> platforms(platform_count);
  check_cl(clGetPlatformIDs(platform_count, platforms.data(), nullptr), "clGetPlatformIDs");

  std::vector<DeviceEntry> devices;
  for (cl_platform_id platform : platforms) {
    cl_uint count = 0;
    if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 0, nullptr, &count) != CL_SUCCESS ||
        count == 0)
      continue;
    std::vector<cl_device_id> ids(count);
    check_cl(clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr),
             "clGetDeviceIDs");
    const std::string platform_name = platform_string(platform, CL_PLATFORM_NAME);
    for (cl_device_id id : ids) {
      DeviceEntry e;
      e.platform = platform;
      e.device = id;
      e.name = device_string(id, CL_DEVICE_NAME);
      e.platform_name = platform_name;
      clGetDeviceInfo(id, CL_DEVICE_TYPE, sizeof e.type, &e.type, nullptr);
      clGetDeviceInfo(id, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof e.compute_units, &e.compute_units,
                      nullptr);
      clGetDeviceInfo(id, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof e.global_memory, &e.global_memory,
                      nullptr);
      devices.push_back(e);
    }
  }
  check(!devices.empty(), "no OpenCL device found on ", platforms.size(), " platform(s): ",
        kNoPlatformAdvice);
  return devices;
}

static std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

DeviceEntry select_device(const std::string& spec) {
  const std::vector<DeviceEntry> devices = enumerate_devices();
  if (spec.empty()) return devices.front();
  std::string listing;
  for (size_t i = 0; i < devices.size(); ++i)
    listing += "\n  " + std::to_string(i) + ": " + devices[i].describe();
  const bool is_index =
      std::all_of(spec.begin(), spec.end(), [](unsigned char c) { return std::isdigit(c); });
  if (is_index) {
    const unsigned long index = std::stoul(spec);
    check(index < devices.size(), "OpenCL device index ", spec, " is out of range; there ",
          devices.size() == 1 ? "is 1 device:" : "are several devices:", listing);
    return devices[index];
  }
  const std::string wanted = lower(spec);
  for (const DeviceEntry& d : devices)
    if (lower(d.name).find(wanted) != std::string::npos ||
        lower(d.platform_name).find(wanted) != std::string::npos)
      return d;
  fail("no OpenCL device matches '", spec, "'; use an index or part of a name of:", listing);
}

Context::Context(const DeviceEntry& device) : entry_(device) {
  cl_int status = CL_SUCCESS;
  cl_context_properties props[] = {CL_CONTEXT_PLATFORM,
                                   reinterpret_cast<cl_context_properties>(device.platform), 0};
  context_ = clCreateContext(props, 1, &entry_.device, nullptr, nullptr, &status);
  check_cl(status, "clCreateContext");
  queue_ = clCreateCommandQueue(context_, entry_.device, 0, &status);
  if (status != CL_SUCCESS) {
    clReleaseContext(context_);
    check_cl(status, "clCreateCommandQueue");
  }
  compiler_identity_ = entry_.name + "|" + device_string(entry_.device, CL_DRIVER_VERSION) + "|" +
                       device_string(entry_.device, CL_DEVICE_VERSION) + "|" +
                       platform_string(entry_.platform, CL_PLATFORM_VERSION);
}

Context::~Context() {
  if (queue_) {
    clFinish(queue_);
    clReleaseCommandQueue(queue_);
  }
  if (context_) clReleaseContext(context_);
}

void Context::finish() const { check_cl(clFinish(queue_), "clFinish"); }

}  // namespace facetool::opencl
