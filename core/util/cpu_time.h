// CPU time clocks: timings that other processes on the machine do not skew.
#pragma once

#include <time.h>

namespace facetool {

// Seconds of CPU time the calling thread has used (phase timings).
inline double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// Seconds of CPU time the whole process (all threads) has used. On a machine shared with other
// work the wall time also counts the time spent waiting for a core; the CPU time does not
// (facetool's threads sleep while they wait, so it is the work done).
inline double process_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace facetool
