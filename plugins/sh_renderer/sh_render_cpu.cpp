// CPU entries of the sh_renderer kernel: kernels/sh_render.cl compiled as C++, item by item.
#include <cmath>

#include "plugins/sh_renderer/sh_render_kernel.h"

namespace facetool::sh_render {
namespace cl {
#include "kernels/sh_render.cl"
}  // namespace cl

namespace {

using I = int;

void forward(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    cl::sh_forward_item(static_cast<I>(item), a.tensor(0), a.tensor(1), a.tensor(2), a.tensor(3),
                        a.tensor(4), a.tensor(5), a.tensor(6), a.tensor(7), a.tensor(8),
                        a.int_arg(9), a.int_arg(10), a.int_arg(11));
}

void backward(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    cl::sh_backward_item(static_cast<I>(item), a.tensor(0), a.tensor(1), a.tensor(2),
                         a.tensor(3), a.tensor(4), a.tensor(5), a.tensor(6), a.tensor(7),
                         a.tensor(8), a.tensor(9), a.tensor(10), a.tensor(11), a.tensor(12),
                         a.int_arg(13), a.int_arg(14), a.int_arg(15), a.int_arg(16));
}

void light_partial(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    cl::sh_light_partial_item(static_cast<I>(item), a.tensor(0), a.tensor(1), a.tensor(2),
                              a.int_arg(3), a.int_arg(4), a.int_arg(5));
}

void reduce_rows(const CpuKernelArgs& a, int64_t begin, int64_t end) {
  for (int64_t item = begin; item < end; ++item)
    cl::sh_reduce_rows_item(static_cast<I>(item), a.tensor(0), a.tensor(1), a.int_arg(2),
                            a.int_arg(3), a.int_arg(4), a.int_arg(5));
}

}  // namespace

std::map<std::string, CpuKernelFn> cpu_entries() {
  return {{kForwardEntry, &forward},
          {kBackwardEntry, &backward},
          {kLightPartialEntry, &light_partial},
          {kReduceRowsEntry, &reduce_rows}};
}

}  // namespace facetool::sh_render
