// The CPU twins of lambertian.cl (the same file compiled as C++) and the CustomKernel holding both.
#include "lambertian_kernel.h"

#include <cmath>
#include <string>

#include "core/util/error.h"

namespace lambertian_kernels {
const char* kernel_source(const std::string& file_name);  // made by facetool_embed_kernels
}

namespace lambertian {
namespace {

#include "lambertian.cl"

using facetool::CpuKernelArgs;

void forward_cpu(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    lb_forward_item(static_cast<int>(item), a.tensor(0), a.tensor(1), a.tensor(2), a.tensor(3),
                    a.tensor(4), a.tensor(5), a.int_arg(6), a.int_arg(7));
}

void backward_cpu(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    lb_backward_item(static_cast<int>(item), a.tensor(0), a.tensor(1), a.tensor(2), a.tensor(3),
                     a.tensor(4), a.tensor(5), a.tensor(6), a.tensor(7), a.int_arg(8),
                     a.int_arg(9), a.int_arg(10));
}

void light_cpu(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    lb_light_item(static_cast<int>(item), a.tensor(0), a.tensor(1), a.tensor(2), a.tensor(3),
                  a.tensor(4), a.tensor(5), a.int_arg(6), a.int_arg(7), a.int_arg(8));
}

}  // namespace

const facetool::CustomKernel& kernel() {
  static const facetool::CustomKernel k = [] {
    const char* source = lambertian_kernels::kernel_source("lambertian.cl");
    facetool::check(source != nullptr, "lambertian: lambertian.cl was not embedded");
    facetool::CustomKernel made;
    made.name = "example_lambertian";
    made.opencl_source = source;
    made.cpu_entries = {{"lambertian_forward", forward_cpu},
                        {"lambertian_backward", backward_cpu},
                        {"lambertian_light", light_cpu}};
    return made;
  }();
  return k;
}

}  // namespace lambertian
