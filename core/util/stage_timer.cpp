// Stage timing: a process-wide table of totals behind a mutex, switched on by benchmarks.
#include "core/util/stage_timer.h"

#include <atomic>
#include <cstring>
#include <mutex>

namespace facetool {
namespace {

std::atomic<bool> enabled{false};
std::mutex mutex;
std::vector<StageTotal>& table() {
  static std::vector<StageTotal> totals;
  return totals;
}

}  // namespace

void enable_stage_timing(bool on) { enabled.store(on); }
bool stage_timing_enabled() { return enabled.load(std::memory_order_relaxed); }

std::vector<StageTotal> stage_totals() {
  std::lock_guard<std::mutex> lock(mutex);
  return table();
}

void reset_stage_totals() {
  std::lock_guard<std::mutex> lock(mutex);
  table().clear();
}

void add_stage_time(const char* stage, double seconds) {
  std::lock_guard<std::mutex> lock(mutex);
  for (StageTotal& t : table()) {
    if (t.stage == stage) {
      t.seconds += seconds;
      ++t.calls;
      return;
    }
  }
  table().push_back(StageTotal{stage, seconds, 1});
}

}  // namespace facetool
