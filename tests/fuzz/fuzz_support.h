// Helpers shared by the fuzz targets: invariant checks that abort, and a scratch file per process.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace facetool::fuzz {

// A parser broke its own contract (an accepted input with an impossible result): abort, so that
// libFuzzer keeps the input and the replay test fails.
inline void require(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what);
  std::abort();
}

// A path `name` inside a scratch folder of this process (created once, under TMPDIR or /tmp),
// for parsers that only read files.
std::string scratch_path(const std::string& name);
// Writes the bytes to `path` (replacing it); aborts if that fails, since no result would mean
// anything then.
void write_file(const std::string& path, const uint8_t* data, size_t size);

}  // namespace facetool::fuzz
