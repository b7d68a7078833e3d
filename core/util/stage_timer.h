// Wall-clock totals per named stage of a run (decode, detect, encode, fsync, ...) for benchmarks.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace facetool {

// Off unless enabled: a disabled StageTimer reads no clock and takes no lock.
void enable_stage_timing(bool enabled);
bool stage_timing_enabled();
// (stage, total seconds, calls) in order of first use; reset clears them.
struct StageTotal {
  std::string stage;
  double seconds = 0.0;
  long calls = 0;
};
std::vector<StageTotal> stage_totals();
void reset_stage_totals();
void add_stage_time(const char* stage, double seconds);

// Adds the time from construction to destruction to `stage` (a string literal).
class StageTimer {
 public:
  explicit StageTimer(const char* stage)
      : stage_(stage_timing_enabled() ? stage : nullptr),
        start_(stage_ ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point()) {}
  ~StageTimer() {
    if (stage_)
      add_stage_time(stage_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  const char* stage_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace facetool
