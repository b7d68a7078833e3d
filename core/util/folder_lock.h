// One run per output folder: an advisory lock (flock) on the folder itself while a run writes.
#pragma once

#include <string>

namespace facetool {

// Holds an flock on an output folder for as long as it lives (the kernel releases it when the
// process ends, even by kill -9). No lock file is left behind: the folder's own descriptor is
// locked. An unsharded run (shard_count 1: train, synth, infer, ...) refuses a folder any other
// run holds. The shards of one sharded run (--shard i/n, which write disjoint files) share it:
// each also holds a byte-range lock (open-file-description lock, fcntl F_OFD_SETLK) on the byte
// of its index and on the byte of its count, so that a second process of the same shard, or a
// shard of a run split another way (i/m with m != n), is refused too.
class FolderLock {
 public:
  // Locks `folder` (which must exist) or throws facetool::Error "<what> '<folder>' is in use by
  // another facetool run ...". `what` names the option, e.g. "--out".
  FolderLock(const std::string& folder, const std::string& what, int shard_index = 0,
             int shard_count = 1);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  FolderLock(FolderLock&& other) noexcept;
  FolderLock& operator=(FolderLock&& other) noexcept;

 private:
  void lock_shard(const std::string& folder, const std::string& what, int shard_index,
                  int shard_count);
  int fd_ = -1;
};

}  // namespace facetool
