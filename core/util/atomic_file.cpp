// Atomic file writing (temporary file in the target folder, then rename) and clean-up.
#include "core/util/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <system_error>

#include "core/util/error.h"
#include "core/util/stage_timer.h"

namespace facetool {
namespace fs = std::filesystem;

namespace {
const char kMarker[] = ".tmp-";
}

std::string temporary_path_for(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + kMarker + std::to_string(static_cast<long>(::getpid())) + "-" +
         std::to_string(counter++);
}

void commit_temporary(const std::string& temporary, const std::string& path) {
  StageTimer timer("fsync");  // the rename and the folder's fsync that makes it durable
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temporary.c_str());
    fail("cannot write '", path, "': renaming the finished temporary file failed: ", why);
  }
  // Make the rename itself durable; a failure here loses nothing already on disk.
  const fs::path folder = fs::path(path).parent_path();
  const int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

void write_atomically(const std::string& final_path,
                      const std::function<void(const std::string& temporary)>& write) {
  const std::string temporary = temporary_path_for(final_path);
  try {
    write(temporary);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  commit_temporary(temporary, final_path);
}

std::string write_failure_advice(int error) {
  switch (error) {
    case ENOSPC:
    case EDQUOT:
      return " (the disk is full: free some space and run again; existing files were kept)";
    case EACCES:
    case EPERM:
    case EROFS:
      return " (the folder is not writable: choose another output folder or fix its permissions)";
    case ENOENT:
    case ENOTDIR:
      return " (the folder does not exist: create it first)";
    default:
      return " (existing files were kept)";
  }
}

namespace {
// Writes `size` bytes to `temporary` with every write, the fsync and the close checked; errors
// name `path`, the file the temporary stands for.
void write_checked(const std::string& temporary, const std::string& path, const void* data,
                   size_t size) {
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int error = errno;
    fail("cannot write '", path, "': ", std::strerror(error), write_failure_advice(error));
  }
  const char* bytes = static_cast<const char*>(data);
  size_t written = 0;
  int error = 0;
  std::optional<StageTimer> write_timer(std::in_place, "write");
  while (written < size) {
    const ssize_t n = ::write(fd, bytes + written, size - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : ENOSPC;
      break;
    }
    written += static_cast<size_t>(n);
  }
  write_timer.reset();
  {
    StageTimer timer("fsync");
    if (error == 0 && ::fsync(fd) != 0) error = errno;
  }
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0)
    fail("cannot write '", path, "': ", std::strerror(error), write_failure_advice(error));
}
}  // namespace

void write_file_atomically(const std::string& path, const void* data, size_t size) {
  write_atomically(path, [&](const std::string& temporary) {
    write_checked(temporary, path, data, size);
  });
}

void write_files_atomically(const std::vector<FileContents>& files) {
  std::vector<std::string> temporaries;
  try {
    for (const FileContents& file : files) {
      temporaries.push_back(temporary_path_for(file.path));
      write_checked(temporaries.back(), file.path, file.bytes.data(), file.bytes.size());
    }
  } catch (...) {
    for (const std::string& temporary : temporaries) std::remove(temporary.c_str());
    throw;
  }
  for (size_t i = 0; i < files.size(); ++i) commit_temporary(temporaries[i], files[i].path);
}

void write_text_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(path, text.data(), text.size());
}

namespace {
// The pid in "<name>.tmp-<pid>-<counter>", or -1 when the name is not of that form.
long temporary_pid(const std::string& file_name) {
  const size_t marker = file_name.rfind(kMarker);
  if (marker == std::string::npos) return -1;
  const size_t start = marker + sizeof(kMarker) - 1, dash = file_name.find('-', start);
  if (dash == std::string::npos || dash == start || dash - start > 9 || dash + 1 >= file_name.size())
    return -1;
  for (size_t k = start; k < file_name.size(); ++k)
    if (k != dash && (file_name[k] < '0' || file_name[k] > '9')) return -1;
  return std::stol(file_name.substr(start, dash - start));
}
}  // namespace

bool is_temporary_file_name(const std::string& file_name) { return temporary_pid(file_name) > 0; }

int remove_stale_temporary_files(const std::string& directory) {
  int removed = 0;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(directory, error)) {
    if (!entry.is_regular_file()) continue;
    const long pid = temporary_pid(entry.path().filename().string());
    if (pid <= 0) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM) continue;  // still running
    std::error_code ignored;
    if (fs::remove(entry.path(), ignored)) ++removed;
  }
  return removed;
}

}  // namespace facetool
