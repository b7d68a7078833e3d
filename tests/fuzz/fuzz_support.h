// Helper shared by the fuzz targets: invariant checks that abort.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace facetool::fuzz {

// A parser broke its own contract (an accepted input with an impossible result): abort, so that
// libFuzzer keeps the input and the replay test fails.
inline void require(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
  std::abort();
}

}  // namespace facetool::fuzz
