// The CPU time of the whole process (all threads), for benchmarks beside their wall times.
#pragma once

#include <ctime>

namespace facetool {

// Seconds of CPU time the process has used. On a machine shared with other work the wall time
// also counts the time spent waiting for a core; the CPU time does not (facetool's threads sleep
// while they wait, so it is the work done).
inline double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace facetool
