// Checking an input file before reading it: it exists, is a regular file and is readable.
#pragma once

#include <string>

namespace facetool {

// Throws facetool::Error "<what> '<path>' ..." saying what is wrong and what to do when `path`
// does not exist, is a folder or another non-regular file (device, pipe), or cannot be opened
// for reading. `what` names the role, e.g. "light file", "--model".
void check_input_file(const std::string& path, const std::string& what);

}  // namespace facetool
