// FolderLock: flock(LOCK_NB) on an O_DIRECTORY descriptor of the output folder, and for shards
// open-file-description byte-range read locks on it (a directory opens read-only, so only read
// locks can be set; F_OFD_GETLK asking for a write lock finds another holder's read lock).
#include "core/util/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>

#include "core/util/error.h"

namespace facetool {
namespace {

// Byte offsets of the shard locks: the index i at i, the count n at kCountBytes + n.
constexpr off_t kCountBytes = off_t{1} << 40;
constexpr off_t kMaxCount = off_t{1} << 31;

bool unsupported(int error) {
  return error == ENOLCK || error == EOPNOTSUPP || error == ENOSYS || error == EINVAL;
}

// Whether another open file description holds a lock on [start, start + length); errno on
// failure (-1).
int held_by_another(int fd, off_t start, off_t length) {
  if (length <= 0) return 0;
  struct flock query {};
  query.l_type = F_WRLCK;
  query.l_whence = SEEK_SET;
  query.l_start = start;
  query.l_len = length;
  if (::fcntl(fd, F_OFD_GETLK, &query) != 0) return -1;
  return query.l_type == F_UNLCK ? 0 : 1;
}

int read_lock(int fd, off_t start) {
  struct flock lock {};
  lock.l_type = F_RDLCK;
  lock.l_whence = SEEK_SET;
  lock.l_start = start;
  lock.l_len = 1;
  int result;
  do {
    result = ::fcntl(fd, F_OFD_SETLK, &lock);
  } while (result != 0 && errno == EINTR);
  return result;
}

}  // namespace

FolderLock::FolderLock(const std::string& folder, const std::string& what, int shard_index,
                       int shard_count) {
  fd_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) {
    const int error = errno;
    fail("cannot lock ", what, " '", folder, "' for this run: ", std::strerror(error));
  }
  const bool sharded = shard_count > 1;
  const int operation = (sharded ? LOCK_SH : LOCK_EX) | LOCK_NB;
  int result;
  do {
    result = ::flock(fd_, operation);
  } while (result != 0 && errno == EINTR);
  if (result != 0) {
    const int error = errno;
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK)
      fail(what, " '", folder, "' is in use by another facetool run writing there; wait for it "
           "to finish or choose another folder (two runs into one folder would mix their files)");
    // File systems without flock (some network mounts): run unguarded rather than not at all.
    if (unsupported(error)) return;
    fail("cannot lock ", what, " '", folder, "' for this run: ", std::strerror(error));
  }
  if (sharded) {
    try {
      lock_shard(folder, what, shard_index, shard_count);
    } catch (...) {
      ::close(fd_);
      fd_ = -1;
      throw;
    }
  }
}

void FolderLock::lock_shard(const std::string& folder, const std::string& what, int shard_index,
                            int shard_count) {
  check(shard_index >= 0 && shard_index < shard_count && shard_count < kMaxCount,
        "shard ", shard_index, "/", shard_count, " is not valid");
  const off_t index_byte = shard_index, count_byte = kCountBytes + shard_count;
  // Set first, then look for other holders: two processes starting together both see each
  // other and both refuse, never both run.
  if (read_lock(fd_, index_byte) != 0 || read_lock(fd_, count_byte) != 0) {
    const int error = errno;
    if (unsupported(error)) return;  // no byte-range locks here: the flock alone guards
    fail("cannot lock ", what, " '", folder, "' for this run: ", std::strerror(error));
  }
  const int same_shard = held_by_another(fd_, index_byte, 1);
  const int other_split =
      same_shard != 0 ? 0
                      : std::max(held_by_another(fd_, kCountBytes, shard_count),
                                 held_by_another(fd_, count_byte + 1, kMaxCount - shard_count));
  if (same_shard < 0 || other_split < 0) {
    const int error = errno;
    if (unsupported(error)) return;
    fail("cannot lock ", what, " '", folder, "' for this run: ", std::strerror(error));
  }
  if (same_shard > 0)
    fail(what, " '", folder, "' is in use by another facetool run of shard ", shard_index, "/",
         shard_count, " writing there; wait for it to finish or give each process its own "
         "shard (two processes of one shard would write the same files)");
  if (other_split > 0)
    fail(what, " '", folder, "' is in use by another facetool run split into another number "
         "of shards; give every shard of one run the same --shard i/", shard_count,
         " or choose another folder (shards of two splittings would write the same files)");
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the descriptor releases the locks
}

FolderLock::FolderLock(FolderLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

FolderLock& FolderLock::operator=(FolderLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

}  // namespace facetool
