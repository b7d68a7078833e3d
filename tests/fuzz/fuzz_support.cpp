// Scratch files for the fuzz targets whose parsers read paths.
#include "tests/fuzz/fuzz_support.h"

#include <stdlib.h>
#include <unistd.h>

namespace facetool::fuzz {

std::string scratch_path(const std::string& name) {
  static const std::string folder = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/facetool-fuzz-XXXXXX";
    require(mkdtemp(pattern.data()) != nullptr, "cannot create a scratch folder");
    return pattern;
  }();
  return folder + "/" + name;
}

void write_file(const std::string& path, const uint8_t* data, size_t size) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  require(file != nullptr, "cannot open the scratch file");
  const bool written = size == 0 || std::fwrite(data, 1, size, file) == size;
  require(std::fclose(file) == 0 && written, "cannot write the scratch file");
}

}  // namespace facetool::fuzz
