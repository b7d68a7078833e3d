// Atomic file writing (temporary file in the target folder, then rename) and clean-up.
#include "core/io/atomic_file.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "core/util/error.h"

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
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temporary.c_str());
    fail("cannot write '", path, "': ", why);
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

void write_file_atomically(const std::string& path, const void* data, size_t size) {
  write_atomically(path, [&](const std::string& temporary) {
    FILE* f = std::fopen(temporary.c_str(), "wb");
    check(f != nullptr, "cannot write '", path, "': ", std::strerror(errno),
          " (does the folder exist and is it writable?)");
    const bool ok = std::fwrite(data, 1, size, f) == size && std::fflush(f) == 0 &&
                    ::fsync(::fileno(f)) == 0;
    const std::string why = std::strerror(errno);
    std::fclose(f);
    check(ok, "cannot write '", path, "': ", why, " (disk full?)");
  });
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
