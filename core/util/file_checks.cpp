// check_regular_input_file and read_regular_input_file: stat, open, then one bounded read.
#include "core/util/file_checks.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
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

}  // namespace facetool
