// ProgramCache: in-memory map of built programs plus an on-disk binary cache keyed by a hash.
#include "backends/opencl/program_cache.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "core/util/atomic_file.h"
#include "core/util/error.h"

namespace facetool::opencl {
namespace {

// 64-bit FNV-1a: stable across compilers and runs, unlike std::hash.
uint64_t fnv1a(const std::string& text, uint64_t hash = 1469598103934665603ull) {
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

std::string hex(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::string build_log(cl_program program, cl_device_id device) {
  size_t size = 0;
  if (clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size) !=
      CL_SUCCESS)
    return "(no build log available)";
  std::string log(size, '\0');
  clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  return log.empty() ? "(empty build log)" : log;
}

}  // namespace

std::string default_program_cache_dir() {
  if (const char* dir = std::getenv("FACETOOL_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/facetool/opencl";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/facetool/opencl";
  return "";
}

ProgramCache::ProgramCache(const Context& context, std::string cache_dir)
    : context_(context), cache_dir_(std::move(cache_dir)) {}

ProgramCache::~ProgramCache() {
  for (auto& entry : programs_) clReleaseProgram(entry.second);
}

ProgramCache::Stats ProgramCache::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

std::string ProgramCache::cache_file(const std::string& source, const std::string& options) const {
  if (cache_dir_.empty()) return "";
  uint64_t h = fnv1a(context_.compiler_identity());
  h = fnv1a(std::string(1, '\0') + options, h);
  h = fnv1a(std::string(1, '\0') + source, h);
  return cache_dir_ + "/" + hex(h) + ".clbin";
}

cl_program ProgramCache::get(const std::string& name, const std::string& source,
                             const std::string& options) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string key = options + '\0' + source;
  auto found = programs_.find(key);
  if (found != programs_.end()) {
    ++stats_.memory_hits;
    return found->second;
  }
  const std::string path = cache_file(source, options);
  cl_program program = path.empty() ? nullptr : load_binary(path, options);
  if (program) {
    ++stats_.disk_hits;
  } else {
    program = compile(name, source, options);
    ++stats_.compiles;
    if (!path.empty()) store_binary(program, path);
  }
  programs_.emplace(key, program);
  return program;
}

cl_program ProgramCache::load_binary(const std::string& path, const std::string& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return nullptr;
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (bytes.empty()) return nullptr;
  const unsigned char* data = bytes.data();
  const size_t size = bytes.size();
  cl_int binary_status = CL_SUCCESS;
  cl_int status = CL_SUCCESS;
  cl_device_id device = context_.device();
  cl_program program = clCreateProgramWithBinary(context_.context(), 1, &device, &size, &data,
                                                 &binary_status, &status);
  if (status != CL_SUCCESS || binary_status != CL_SUCCESS) {
    if (program) clReleaseProgram(program);
    return nullptr;  // corrupt or stale: compile from source instead
  }
  if (clBuildProgram(program, 1, &device, options.c_str(), nullptr, nullptr) != CL_SUCCESS) {
    clReleaseProgram(program);
    return nullptr;
  }
  return program;
}

cl_program ProgramCache::compile(const std::string& name, const std::string& source,
                                 const std::string& options) {
  const char* text = source.c_str();
  const size_t length = source.size();
  cl_int status = CL_SUCCESS;
  cl_program program = clCreateProgramWithSource(context_.context(), 1, &text, &length, &status);
  check_cl(status, "clCreateProgramWithSource");
  cl_device_id device = context_.device();
  status = clBuildProgram(program, 1, &device, options.c_str(), nullptr, nullptr);
  if (status != CL_SUCCESS) {
    const std::string log = build_log(program, device);
    clReleaseProgram(program);
    fail("OpenCL program '", name, "' failed to build (", error_string(status), ") with options '",
         options, "' on ", context_.device_entry().name, ". Build log:\n", log);
  }
  return program;
}

void ProgramCache::store_binary(cl_program program, const std::string& path) {
  size_t size = 0;
  if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, nullptr) !=
          CL_SUCCESS ||
      size == 0)
    return;
  std::vector<unsigned char> bytes(size);
  unsigned char* data = bytes.data();
  if (clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof data, &data, nullptr) != CL_SUCCESS)
    return;
  // A cache that cannot be written only costs time on the next run, so failures are ignored.
  std::error_code ec;
  std::filesystem::create_directories(cache_dir_, ec);
  try {
    write_file_atomically(path, data, size);
  } catch (const Error&) {
    // ignored, as said above: the temporary is gone and no partial binary is left behind
  }
}

}  // namespace facetool::opencl
