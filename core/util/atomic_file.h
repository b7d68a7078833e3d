// Writing files so that a reader never sees a half-written one: temporary name, then rename.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace facetool {

// After enable_input_protection() (the facetool program calls it first thing), marks the regular
// file `path` (by device and inode, so any spelling or link of it) as an input of this process: no
// atomic write below may then replace it: the rename is refused with a message naming the file,
// the temporary removed, the input untouched. The photo, image, environment-map and light readers
// call it (not the sample EXR reader: synth regenerates damaged samples it has read). Nothing is
// unmarked: a command never means to replace a photo or light it read. Without the call (a
// program using the library that rewrites a file it read), nothing is marked. Independently, an
// atomic write never replaces an existing path that is not a regular file (a device, a pipe, a
// socket, a folder).
void enable_input_protection();
void protect_input_file(const std::string& path);

// A fresh temporary path beside `path`: "<path>.tmp-<pid>-<counter>" (unique per call).
std::string temporary_path_for(const std::string& path);
// Renames `temporary` over `path` (atomic on one file system); on failure removes the temporary
// and throws facetool::Error.
void commit_temporary(const std::string& temporary, const std::string& path);

// Calls write(temporary) with a temporary_path_for(final_path), then renames it to final_path.
// If write throws, the temporary is removed and the exception propagates.
void write_atomically(const std::string& final_path,
                      const std::function<void(const std::string& temporary)>& write);
// Writes `size` bytes atomically: every write, the fsync and the close are checked, and only
// then is the temporary renamed over `path`. On failure `path` is untouched, the temporary is
// removed, and facetool::Error names `path`, the OS reason and what to do.
void write_file_atomically(const std::string& path, const void* data, size_t size);
// A file's final path and its whole contents.
struct FileContents {
  std::string path;
  std::vector<unsigned char> bytes;
};
// Writes several files that belong together: every temporary is written and checked first, and
// only when all succeeded are they renamed; on failure none of the paths is touched.
void write_files_atomically(const std::vector<FileContents>& files);

// Files written together, made durable together. While a WriteBatch is open on a thread, every
// atomic write of that thread (write_atomically and what is built on it) leaves its finished
// temporary unsynced and unrenamed; commit() then makes all of them durable with one syncfs per
// file system they are on, renames them over their final paths and fsyncs each folder once: one
// flush for a photo's ~20 files instead of two per file. Destroyed without commit() (a write
// failed), it removes the temporaries and no final path is touched. A batch opened while
// another is open on the thread joins the outer one (its commit() does nothing).
class WriteBatch {
 public:
  WriteBatch();
  ~WriteBatch();
  WriteBatch(const WriteBatch&) = delete;
  WriteBatch& operator=(const WriteBatch&) = delete;
  // Syncs, renames and syncs the folders; on failure removes the temporaries not yet renamed
  // and throws facetool::Error naming the file and what to do.
  void commit();

 private:
  bool outer_;
};

// The same for text (light files, manifests, JSON).
void write_text_atomically(const std::string& path, const std::string& text);
// What to do after a write failed with errno `error` (" (the disk is full: ...)").
std::string write_failure_advice(int error);

// Temporaries being written are registered until they are renamed or removed; a fatal signal
// (SIGINT, SIGTERM, SIGHUP, SIGQUIT) removes them before the process ends, so no "*.tmp-PID-N"
// survives an interrupted run. Installs those handlers (facetool's main does, once); a command
// that handles a signal itself (train) replaces the handler for that signal.
void remove_temporaries_on_fatal_signals();
// Removes every registered temporary (async-signal-safe: unlink only).
void remove_registered_temporaries() noexcept;

// True for names temporary_path_for produces.
bool is_temporary_file_name(const std::string& file_name);
// Removes leftover temporaries of interrupted runs in `directory` (those whose process is gone;
// files of running processes, e.g. other shards writing there, are left alone). Returns how many.
int remove_stale_temporary_files(const std::string& directory);

}  // namespace facetool
