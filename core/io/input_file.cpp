// Input-file checks that turn stream and library errors into messages naming the file.
#include "core/io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/util/error.h"

namespace facetool {

void check_input_file(const std::string& path, const std::string& what) {
  check(!path.empty(), what, ": the file name is empty; give the path of a file");
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    const int error = errno;
    if (error == ENOENT) fail(what, " '", path, "' does not exist (no such file); check the path");
    fail(what, " '", path, "' cannot be read: ", std::strerror(error));
  }
  check(!S_ISDIR(info.st_mode), what, " '", path, "' is a folder; give a file inside it");
  check(S_ISREG(info.st_mode), what, " '", path,
        "' is not a regular file (a device, pipe or socket); give an ordinary file");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    fail(what, " '", path, "' cannot be read: ", std::strerror(error),
         error == EACCES ? " (check its permissions)" : "");
  }
  ::close(fd);
}

}  // namespace facetool
