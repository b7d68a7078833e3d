// Plugin kernels: per-item kernels a plugin brings in two forms, OpenCL C and a CPU function.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace facetool {

class Tensor;

// One argument of a kernel launch: a tensor (passed as a float buffer), an int or a float.
// On OpenCL argument i becomes kernel argument i: `__global float*`, `int` or `float`.
struct KernelArg {
  enum class Kind { Tensor, Int, Float };
  Kind kind = Kind::Int;
  const Tensor* tensor = nullptr;
  int32_t int_value = 0;
  float float_value = 0.0f;

  static KernelArg of(const Tensor& t) { return {Kind::Tensor, &t, 0, 0.0f}; }
  static KernelArg of(int32_t v) { return {Kind::Int, nullptr, v, 0.0f}; }
  static KernelArg of(float v) { return {Kind::Float, nullptr, 0, v}; }
};

// What a CPU kernel function sees: argument i by position, with its host pointer or value.
class CpuKernelArgs {
 public:
  explicit CpuKernelArgs(std::vector<float*> pointers, std::vector<KernelArg> args)
      : pointers_(std::move(pointers)), args_(std::move(args)) {}
  float* tensor(size_t i) const { return pointers_.at(i); }
  int32_t int_arg(size_t i) const { return args_.at(i).int_value; }
  float float_arg(size_t i) const { return args_.at(i).float_value; }
  size_t size() const { return args_.size(); }

 private:
  std::vector<float*> pointers_;
  std::vector<KernelArg> args_;
};

// Processes items [begin, end) of a launch. Called concurrently on disjoint ranges, so it
// must only write what its own items own.
using CpuKernelFn = void (*)(const CpuKernelArgs& args, int64_t begin, int64_t end);

// A named program: OpenCL source holding one `__kernel` per entry, and a CPU function per entry
// with the same semantics. The OpenCL kernel is launched with a 1-D global size equal to the
// number of work items and must not assume any work-group size; its last argument need not
// carry the item count (pass it explicitly as an int if the kernel needs it).
struct CustomKernel {
  std::string name;           // unique program name, e.g. "sh_renderer"; the cache key with source
  std::string opencl_source;  // OpenCL C 1.2
  std::string build_options;  // extra options for clBuildProgram, e.g. "-DCHANNELS=3"
  std::map<std::string, CpuKernelFn> cpu_entries;  // entry name -> CPU implementation
};

}  // namespace facetool
