// CPU time of the calling thread: phase timings that other processes on the machine do not skew.
#pragma once

#include <time.h>

namespace facetool {

inline double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

}  // namespace facetool
