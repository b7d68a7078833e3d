// cached_weight_transform: results keyed by the weights' address and checked against their values.
#include "backends/cpu/cpu_weight_cache.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <list>
#include <mutex>
#include <tuple>

namespace facetool::cpu {
namespace {

struct Entry {
  const float* w;
  std::vector<float> raw;  // the weights' values when `result` was computed
  std::shared_ptr<const std::vector<float>> result;
  size_t bytes() const { return (raw.size() + result->size()) * sizeof(float); }
};

struct Cache {
  std::mutex mutex;
  std::list<Entry> entries;  // most recently used first
  size_t bytes = 0;
};

Cache& cache() {
  static Cache* c = new Cache;  // lives until exit: callers may run during static destruction
  return *c;
}

}  // namespace

std::shared_ptr<const std::vector<float>> cached_weight_transform(
    const float* w, size_t raw, size_t floats,
    const std::function<void(const float* w, float* out)>& transform) {
  Cache& c = cache();
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    for (auto it = c.entries.begin(); it != c.entries.end(); ++it) {
      if (it->w != w || it->raw.size() != raw || it->result->size() != floats)
        continue;
      if (std::memcmp(it->raw.data(), w, raw * sizeof(float)) != 0) {
        c.bytes -= it->bytes();
        c.entries.erase(it);  // the weights changed: computed anew below
        break;
      }
      c.entries.splice(c.entries.begin(), c.entries, it);
      return it->result;
    }
  }
  // Computed outside the lock (the transform may run parallel_for); a second thread asking for
  // the same weights meanwhile computes them too, and the later insertion replaces the earlier.
  auto result = std::make_shared<std::vector<float>>(floats);
  transform(w, result->data());
  Entry entry{w, std::vector<float>(w, w + raw), result};
  const size_t entry_bytes = entry.bytes();
  if (entry_bytes > kWeightCacheBytes) return result;
  std::lock_guard<std::mutex> lock(c.mutex);
  for (auto it = c.entries.begin(); it != c.entries.end(); ++it) {
    if (it->w == w) {
      c.bytes -= it->bytes();
      c.entries.erase(it);
      break;
    }
  }
  while (!c.entries.empty() && c.bytes + entry_bytes > kWeightCacheBytes) {
    c.bytes -= c.entries.back().bytes();
    c.entries.pop_back();
  }
  c.bytes += entry_bytes;
  c.entries.push_front(std::move(entry));
  return result;
}

}  // namespace facetool::cpu
