// check_regular_input_file and read_regular_input_file: stat, open, then one bounded read.
#include "core/util/file_checks.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <fstream>

#include "core/util/error.h"

namespace facetool {

uint64_t check_regular_input_file(const std::string& path, uint64_t max_bytes,
                                  const std::string& what) {
  check(!path.empty(), what, ": the file name is empty; give the path of a file");
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    const int error = errno;
    if (error == ENOENT) fail(what, " '", path, "' does not exist (no such file); check the path");
    if (error == ENOTDIR)
      fail(what, " '", path, "' does not exist: a part of the path before the file name is a ",
           "file, not a folder; check the path");
    if (error == ELOOP)
      fail(what, " '", path, "' is a loop of symbolic links; point the link at a real file");
    fail(what, " '", path, "' cannot be read: ", std::strerror(error));
  }
  if (S_ISDIR(info.st_mode)) fail(what, " '", path, "' is a folder; give a file inside it");
  if (!S_ISREG(info.st_mode))
    fail(what, " '", path,
         "' is not a regular file (a device, pipe or socket); give an ordinary file");
  const uint64_t size = static_cast<uint64_t>(info.st_size);
  if (size > max_bytes)
    fail(what, " '", path, "' holds ", size, " bytes, more than the ", max_bytes,
         "-byte limit for such files; is it the right file?");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    fail(what, " '", path, "' cannot be read: ", std::strerror(error),
         error == EACCES ? " (check its permissions)" : "");
  }
  ::close(fd);
  return size;
}

std::string read_regular_input_file(const std::string& path, uint64_t max_bytes,
                                    const std::string& what) {
  const uint64_t size = check_regular_input_file(path, max_bytes, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(what, " '", path, "' cannot be read: ", std::strerror(errno));
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<uint64_t>(in.gcount()) != size)
    fail("cannot read ", what, " '", path, "': it changed or could not be read completely");
  return bytes;
}

void check_input_folder(const std::string& path, const std::string& what) {
  check(!path.empty(), what, ": the folder name is empty; give the path of a folder");
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    const int error = errno;
    if (error == ENOENT)
      fail(what, " '", path, "' does not exist (no such folder); check the path");
    if (error == ENOTDIR)
      fail(what, " '", path, "' does not exist: a part of the path is a file, not a folder");
    if (error == ELOOP)
      fail(what, " '", path, "' is a loop of symbolic links; point the link at a real folder");
    fail(what, " '", path, "' cannot be read: ", std::strerror(error));
  }
  if (!S_ISDIR(info.st_mode))
    fail(what, " '", path, "' is ", S_ISREG(info.st_mode) ? "a file" : "a device, pipe or socket",
         ", not a folder; give the folder that holds the files");
  if (::access(path.c_str(), R_OK | X_OK) != 0) {
    const int error = errno;
    fail(what, " '", path, "' cannot be read: ", std::strerror(error), " (check its permissions)");
  }
}

std::vector<std::string> list_folder_files(const std::string& folder, const std::string& what,
                                           bool (*keep)(const std::string& file_name),
                                           std::vector<std::string>& problems) {
  namespace fs = std::filesystem;
  check_input_folder(folder, what);
  std::vector<std::string> files;
  std::error_code error;
  fs::directory_iterator it(folder, error);
  if (error) fail(what, " '", folder, "' cannot be listed: ", error.message());
  for (; it != fs::directory_iterator(); it.increment(error)) {
    if (error) fail(what, " '", folder, "' cannot be listed: ", error.message());
    const fs::path& entry = it->path();
    if (!keep(entry.filename().string())) continue;
    // lstat, then stat: a link's own state and its target's, each without throwing.
    struct stat link_info {}, info {};
    if (::lstat(entry.c_str(), &link_info) != 0) continue;  // removed meanwhile
    if (::stat(entry.c_str(), &info) != 0) {
      const int reason = errno;
      if (S_ISLNK(link_info.st_mode) && reason == ELOOP)
        problems.push_back("'" + entry.string() + "' is a loop of symbolic links");
      else if (S_ISLNK(link_info.st_mode) && reason == ENOENT)
        problems.push_back("'" + entry.string() + "' is a dangling symbolic link (its target does "
                           "not exist)");
      else
        problems.push_back("'" + entry.string() + "' cannot be read: " + std::strerror(reason));
      continue;
    }
    if (S_ISDIR(info.st_mode)) continue;  // a subfolder is not one of the files
    if (!S_ISREG(info.st_mode)) {
      problems.push_back("'" + entry.string() +
                         "' is not a regular file (a device, pipe or socket)");
      continue;
    }
    files.push_back(entry.string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool same_existing_file(const std::string& a, const std::string& b) {
  struct stat x {}, y {};
  return ::stat(a.c_str(), &x) == 0 && ::stat(b.c_str(), &y) == 0 && x.st_dev == y.st_dev &&
         x.st_ino == y.st_ino;
}

void check_output_is_not_an_input(const std::string& output, const std::string& option,
                                  const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs)
    check(!same_existing_file(output, input), option, " '", output, "' is the input '", input,
          "' of this run; writing it would replace that input: choose another output name");
}

void check_inputs_outside_output_folders(const std::vector<std::string>& inputs,
                                         const std::vector<std::string>& folders, const std::string& option) {
  namespace fs = std::filesystem;
  // The folders by canonical path (a set: a run of thousands of photos has as many folders).
  std::map<fs::path, const std::string*> written;
  for (const std::string& folder : folders) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    if (!ec) written.emplace(canonical, &folder);
  }
  for (const std::string& input : inputs) {
    std::error_code ec;
    const fs::path canonical = fs::canonical(input, ec);
    if (ec) continue;  // a missing input is named by its reader
    for (fs::path up = canonical.parent_path(); !up.empty(); up = up.parent_path()) {
      const auto found = written.find(up);
      if (found != written.end())
        fail("the input '", input, "' lies in '", *found->second, "', which this run writes (", option,
             "): it could be replaced; move it or choose another output folder");
      if (up == up.root_path()) break;
    }
  }
}

}  // namespace facetool
