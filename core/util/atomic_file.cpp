// Atomic file writing (temporary file in the target folder, then rename) and clean-up.
#include "core/util/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <system_error>
#include <vector>

#include "core/util/error.h"
#include "core/util/stage_timer.h"

namespace facetool {
namespace fs = std::filesystem;

namespace {
const char kMarker[] = ".tmp-";

// The registry of temporaries being written: fixed slots, so that a signal handler can read it
// without allocating or locking. A slot is 0 (free), 1 (being filled) or 2 (holds a path).
constexpr int kSlots = 512;
constexpr size_t kPathBytes = 4096;
char g_paths[kSlots][kPathBytes];
std::atomic<int> g_slot_state[kSlots];

// Registers `path` for removal on a fatal signal; the slot number, or -1 when all are taken.
int register_temporary(const std::string& path) {
  if (path.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slot_state[i].compare_exchange_strong(expected, 1)) {
      std::memcpy(g_paths[i], path.c_str(), path.size() + 1);
      g_slot_state[i].store(2, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

void unregister_temporary(int slot) {
  if (slot >= 0) g_slot_state[slot].store(0, std::memory_order_release);
}

// Registers a temporary for its lifetime.
class Registered {
 public:
  explicit Registered(const std::string& path) : slot_(register_temporary(path)) {}
  ~Registered() { unregister_temporary(slot_); }
  Registered(const Registered&) = delete;
  Registered& operator=(const Registered&) = delete;

 private:
  int slot_;
};

// The open WriteBatch's temporaries of this thread, in the order they were written.
struct PendingFile {
  std::string temporary, path;
  std::unique_ptr<Registered> registered;
};
thread_local std::vector<PendingFile>* t_batch = nullptr;

extern "C" void remove_temporaries_and_die(int signal) {
  remove_registered_temporaries();
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}
}  // namespace

void remove_registered_temporaries() noexcept {
  for (int i = 0; i < kSlots; ++i)
    if (g_slot_state[i].load(std::memory_order_acquire) == 2) ::unlink(g_paths[i]);
}

void remove_temporaries_on_fatal_signals() {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
    struct sigaction action {};
    action.sa_handler = remove_temporaries_and_die;
    sigemptyset(&action.sa_mask);
    ::sigaction(signal, &action, nullptr);
  }
}

std::string temporary_path_for(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + kMarker + std::to_string(static_cast<long>(::getpid())) + "-" +
         std::to_string(counter++);
}

namespace {

// The files this process has read as inputs (device, inode): protect_input_file.
std::mutex g_inputs_mutex;
std::set<std::pair<dev_t, ino_t>> g_inputs;
std::atomic<bool> g_protect_inputs{false};

bool is_protected_input(dev_t device, ino_t inode) {
  std::lock_guard<std::mutex> lock(g_inputs_mutex);
  return g_inputs.count({device, inode}) > 0;
}

// Renames a finished temporary over `path`, unless `path` is something no result may replace (a
// device, a pipe, a folder, an input of this run); on failure removes it and throws.
void rename_temporary(const std::string& temporary, const std::string& path) {
  struct stat existing;
  if (::stat(path.c_str(), &existing) == 0) {
    const char* refusal = nullptr;
    if (!S_ISREG(existing.st_mode))
      refusal = "is not a regular file (a device, a pipe, a socket or a folder): facetool writes its results only "
                "as new files or over regular files; choose another output name";
    else if (is_protected_input(existing.st_dev, existing.st_ino))
      refusal = "is an input of this run: writing the result there would replace it; choose another output "
                "folder or name";
    if (refusal) {
      std::remove(temporary.c_str());
      fail("refusing to write '", path, "': it ", refusal);
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temporary.c_str());
    fail("cannot write '", path, "': renaming the finished temporary file failed: ", why);
  }
}

std::string folder_of(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  return folder.empty() ? std::string(".") : folder.string();
}

// Makes a rename in `folder` durable; a failure here loses nothing already on disk.
void sync_folder(const std::string& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}
}  // namespace

void enable_input_protection() { g_protect_inputs = true; }

void protect_input_file(const std::string& path) {
  if (!g_protect_inputs) return;
  struct stat st;
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;
  std::lock_guard<std::mutex> lock(g_inputs_mutex);
  g_inputs.insert({st.st_dev, st.st_ino});
}

void commit_temporary(const std::string& temporary, const std::string& path) {
  StageTimer timer("fsync");  // the rename and the folder's fsync that makes it durable
  rename_temporary(temporary, path);
  sync_folder(folder_of(path));
}

void write_atomically(const std::string& final_path,
                      const std::function<void(const std::string& temporary)>& write) {
  const std::string temporary = temporary_path_for(final_path);
  auto registered = std::make_unique<Registered>(temporary);
  try {
    write(temporary);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  if (t_batch) {  // renamed by the batch's commit()
    t_batch->push_back({temporary, final_path, std::move(registered)});
    return;
  }
  commit_temporary(temporary, final_path);
}

WriteBatch::WriteBatch() : outer_(t_batch == nullptr) {
  if (outer_) t_batch = new std::vector<PendingFile>();
}

WriteBatch::~WriteBatch() {
  if (!outer_ || !t_batch) return;
  for (const PendingFile& file : *t_batch) std::remove(file.temporary.c_str());
  delete t_batch;
  t_batch = nullptr;
}

void WriteBatch::commit() {
  if (!outer_ || !t_batch) return;
  std::unique_ptr<std::vector<PendingFile>> files(t_batch);
  t_batch = nullptr;
  StageTimer timer("fsync");
  size_t renamed = 0;
  try {
    // One flush per file system holding temporaries (one, unless a folder is a mount point).
    std::vector<dev_t> flushed;
    for (const PendingFile& file : *files) {
      const int fd = ::open(folder_of(file.temporary).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
      int error = fd < 0 ? errno : 0;
      struct stat status {};
      if (fd >= 0 && ::fstat(fd, &status) == 0 &&
          std::find(flushed.begin(), flushed.end(), status.st_dev) == flushed.end()) {
        if (::syncfs(fd) != 0) error = errno;
        flushed.push_back(status.st_dev);
      }
      if (fd >= 0) ::close(fd);
      if (error != 0)
        fail("cannot write '", file.path, "': ", std::strerror(error), write_failure_advice(error));
    }
    std::vector<std::string> folders;
    for (; renamed < files->size(); ++renamed) {
      const PendingFile& file = (*files)[renamed];
      rename_temporary(file.temporary, file.path);
      const std::string folder = folder_of(file.path);
      if (std::find(folders.begin(), folders.end(), folder) == folders.end()) folders.push_back(folder);
    }
    for (const std::string& folder : folders) sync_folder(folder);
  } catch (...) {
    for (size_t k = renamed; k < files->size(); ++k) std::remove((*files)[k].temporary.c_str());
    throw;
  }
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
    case EFBIG:
      return " (the file-size limit is reached: raise it with ulimit -f, or free the quota; "
             "existing files were kept)";
    default:
      return " (existing files were kept)";
  }
}

namespace {
// Writes `size` bytes to `temporary` with every write, the fsync and the close checked; errors
// name `path`, the file the temporary stands for.
void write_checked(const std::string& temporary, const std::string& path, const void* data,
                   size_t size) {
  const bool sync = t_batch == nullptr;  // a WriteBatch syncs all its files at once
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
    if (error == 0 && sync && ::fsync(fd) != 0) error = errno;
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
  if (t_batch) {  // the open batch gives the all-or-nothing already
    for (const FileContents& file : files) write_file_atomically(file.path, file.bytes.data(), file.bytes.size());
    return;
  }
  std::vector<std::string> temporaries;
  std::vector<std::unique_ptr<Registered>> registered;
  try {
    for (const FileContents& file : files) {
      temporaries.push_back(temporary_path_for(file.path));
      registered.push_back(std::make_unique<Registered>(temporaries.back()));
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
