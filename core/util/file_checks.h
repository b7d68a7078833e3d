// Input files read whole: only regular files of a sane size, so a device, a folder or a huge
// file gives a clear message instead of an endless read or an out-of-memory.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace facetool {

// Size limits of the files facetool reads whole (documented in docs/input-limits.md).
constexpr uint64_t kMaxWeightsFileBytes = uint64_t{8} << 30;  // safetensors weights: 8 GiB
constexpr uint64_t kMaxTextFileBytes = uint64_t{16} << 20;    // light files, JSON: 16 MiB
constexpr uint64_t kMaxMeshFileBytes = uint64_t{2} << 30;     // OBJ meshes: 2 GiB
constexpr uint64_t kMaxImageFileBytes = uint64_t{8} << 30;    // images, EXR files: 8 GiB

// Throws facetool::Error "<what> '<path>' ..." saying what is wrong and what to do unless `path`
// names an existing, readable regular file (not a folder, device or pipe) of at most
// `max_bytes` bytes. `what` names the role, e.g. "light file", "--model". Returns its size.
uint64_t check_regular_input_file(const std::string& path, uint64_t max_bytes,
                                  const std::string& what);

// check_regular_input_file, then the whole content; a short read is an error too.
std::string read_regular_input_file(const std::string& path, uint64_t max_bytes,
                                    const std::string& what);

}  // namespace facetool
