// The sh_renderer's CustomKernel (embedded OpenCL source + CPU entries) and its sparse T table.
#pragma once

#include <map>
#include <string>

#include "core/backend/custom_kernel.h"

namespace facetool::sh_render {

// Entry names (see kernels/sh_render.cl for their arguments).
constexpr const char* kForwardEntry = "sh_render_forward";
constexpr const char* kBackwardEntry = "sh_render_backward";
constexpr const char* kLightPartialEntry = "sh_light_partial";
constexpr const char* kReduceRowsEntry = "sh_reduce_rows";

// Flags of the backward entry (mirrors the SH_* defines of the kernel).
enum BackwardFlags : int {
  kHasDImage = 1,
  kHasDShading = 2,
  kWantAlbedo = 4,
  kWantNormal = 8,
  kWantVisibility = 16,
  kWantLight = 32,
  kAccumulateAlbedo = 64,
  kAccumulateNormal = 128,
  kAccumulateVisibility = 256,
};

const CustomKernel& kernel();
// CPU implementations of every entry (sh_render_cpu.cpp).
std::map<std::string, CpuKernelFn> cpu_entries();

}  // namespace facetool::sh_render
