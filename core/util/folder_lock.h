// One run per output folder: an advisory lock (flock) on the folder itself while a run writes.
#pragma once

#include <string>

namespace facetool {

// Holds an flock on an output folder for as long as it lives (the kernel releases it when the
// process ends, even by kill -9). No lock file is left behind: the folder's own descriptor is
// locked. Exclusive runs (train, synth, infer, ...) refuse a folder any other run holds; shared
// holders (the shards of one sharded run, which write disjoint files) only exclude exclusive ones.
class FolderLock {
 public:
  enum class Mode { kExclusive, kShared };
  // Locks `folder` (which must exist) or throws facetool::Error "<what> '<folder>' is in use by
  // another facetool run ...". `what` names the option, e.g. "--out".
  FolderLock(const std::string& folder, const std::string& what, Mode mode = Mode::kExclusive);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  FolderLock(FolderLock&& other) noexcept;
  FolderLock& operator=(FolderLock&& other) noexcept;

 private:
  int fd_ = -1;
};

}  // namespace facetool
