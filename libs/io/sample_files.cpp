// Sample file names.
#include "libs/io/sample_files.h"

#include <cstdio>

namespace facetool {

std::string sample_file_name(int64_t index) {
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "sample_%08lld.exr", static_cast<long long>(index));
  return buffer;
}

}  // namespace facetool
