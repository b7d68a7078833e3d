// Input files and folders: only regular files of a sane size, so a device, a folder or a huge
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

// Throws facetool::Error unless `path` names an existing folder: "does not exist", "is a file,
// not a folder" or the OS reason, naming `what` (e.g. "--data") and the path.
void check_input_folder(const std::string& path, const std::string& what);

// The regular files of folder `folder` (not recursive) whose names `keep` accepts, sorted.
// Entries that are meant (keep accepts the name) but cannot be read as a regular file, such as a
// dangling symbolic link, a symbolic link loop, a pipe or a device, are not returned: each adds a
// line to `problems` naming the entry and why (the caller skips it with a warning or refuses).
std::vector<std::string> list_folder_files(const std::string& folder, const std::string& what,
                                           bool (*keep)(const std::string& file_name),
                                           std::vector<std::string>& problems);

// True when `a` and `b` both exist and are the same file (same device and inode: hard links,
// symbolic links and different spellings of one path count as the same).
bool same_existing_file(const std::string& a, const std::string& b);

// Throws facetool::Error when output file `output` (given with option `option`) is one of
// `inputs`: writing it would replace an input of the same run.
void check_output_is_not_an_input(const std::string& output, const std::string& option,
                                  const std::vector<std::string>& inputs);

// Before any work: throws facetool::Error naming the input and the folder when one of `inputs`
// lies (at any depth) in one of `folders`, the folders a run writes its results into (e.g.
// <-o>/<photo name>/, whose files it replaces and whose stale sub-folders it removes). Symbolic
// links are resolved; `option` names where the folders come from ("-o DIR").
void check_inputs_outside_output_folders(const std::vector<std::string>& inputs,
                                         const std::vector<std::string>& folders, const std::string& option);

}  // namespace facetool
