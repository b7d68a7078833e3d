// The lambertian renderer's CustomKernel: lambertian.cl for OpenCL plus its CPU twins.
#pragma once

#include "core/backend/custom_kernel.h"

namespace lambertian {

// Entries: "lambertian_forward", "lambertian_backward", "lambertian_light" (lambertian.cl).
const facetool::CustomKernel& kernel();

}  // namespace lambertian
