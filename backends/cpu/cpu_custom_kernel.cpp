// Plugin kernel launches on the cpu: the entry's CPU function over chunks of the work items.
#include <string>

#include "backends/cpu/cpu_backend_impl.h"
#include "core/util/error.h"
#include "core/util/parallel_for.h"

namespace facetool::cpu {

void CpuBackend::launch(const CustomKernel& kernel, const std::string& entry, int64_t work_items,
                        const std::vector<KernelArg>& args) {
  auto found = kernel.cpu_entries.find(entry);
  if (found == kernel.cpu_entries.end() || found->second == nullptr) {
    std::string known;
    for (const auto& [name, fn] : kernel.cpu_entries)
      if (fn) known += (known.empty() ? "" : ", ") + name;
    fail("kernel '", kernel.name, "' has no CPU implementation of entry '", entry,
         "', so it cannot run on the cpu backend (CPU entries: ",
         known.empty() ? "none" : known, "); add one to the plugin or use another backend");
  }
  std::vector<float*> pointers;
  pointers.reserve(args.size());
  for (const KernelArg& a : args)
    pointers.push_back(a.kind == KernelArg::Kind::Tensor ? ptr(*a.tensor) : nullptr);
  const CpuKernelArgs kernel_args(std::move(pointers), args);
  const CpuKernelFn fn = found->second;
  // Small chunks keep threads balanced when items differ in cost.
  const int64_t grain = std::max<int64_t>(1, work_items / (64 * parallel_thread_count()));
  parallel_for(work_items, grain,
               [&](int64_t begin, int64_t end) { fn(kernel_args, begin, end); });
}

}  // namespace facetool::cpu
