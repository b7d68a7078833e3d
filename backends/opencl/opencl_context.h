// OpenCL device discovery, the context and in-order queue of one device, and checked calls.
#pragma once

#include <CL/cl.h>

#include <string>
#include <vector>

namespace facetool::opencl {

// "CL_OUT_OF_RESOURCES (-5)" for an OpenCL error code.
std::string error_string(cl_int code);
// Throws facetool::Error "<what> failed: <error>" unless code == CL_SUCCESS.
void check_cl(cl_int code, const char* what);

struct DeviceEntry {
  cl_platform_id platform = nullptr;
  cl_device_id device = nullptr;
  std::string name;
  std::string platform_name;
  cl_device_type type = 0;
  cl_uint compute_units = 0;
  cl_ulong global_memory = 0;
  // "pthread-... (Portable Computing Language), 2 compute units, 3.8 GiB"
  std::string describe() const;
};

// Every device of every platform, in platform order. Throws facetool::Error with advice when no
// platform or device exists.
std::vector<DeviceEntry> enumerate_devices();
// Picks a device: "" the first one, a decimal index, or a case-insensitive part of its name or
// platform name. Throws facetool::Error listing the devices when nothing matches.
DeviceEntry select_device(const std::string& spec);

std::string device_string(cl_device_id device, cl_device_info info);
std::string platform_string(cl_platform_id platform, cl_platform_info info);

// The context and in-order command queue of one device. Not copyable; releases on destruction.
class Context {
 public:
  explicit Context(const DeviceEntry& device);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceEntry& device_entry() const { return entry_; }
  cl_device_id device() const { return entry_.device; }
  cl_context context() const { return context_; }
  cl_command_queue queue() const { return queue_; }
  // Identifies the compiler that produced a binary: device, driver and platform versions.
  const std::string& compiler_identity() const { return compiler_identity_; }
  bool is_cpu() const { return (entry_.type & CL_DEVICE_TYPE_CPU) != 0; }
  void finish() const;

 private:
  DeviceEntry entry_;
  cl_context context_ = nullptr;
  cl_command_queue queue_ = nullptr;
  std::string compiler_identity_;
};

}  // namespace facetool::opencl
