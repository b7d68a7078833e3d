// FolderLock: flock(LOCK_NB) on an O_DIRECTORY descriptor of the output folder.
#include "core/util/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/util/error.h"

namespace facetool {

FolderLock::FolderLock(const std::string& folder, const std::string& what, Mode mode) {
  fd_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) {
    const int error = errno;
    fail("cannot lock ", what, " '", folder, "' for this run: ", std::strerror(error));
  }
  const int operation = (mode == Mode::kExclusive ? LOCK_EX : LOCK_SH) | LOCK_NB;
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
    if (error == ENOLCK || error == EOPNOTSUPP || error == ENOSYS) return;
    fail("cannot lock ", what, " '", folder, "' for this run: ", std::strerror(error));
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the descriptor releases the lock
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
