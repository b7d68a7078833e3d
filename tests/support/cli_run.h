// Running the facetool executable from a test, and reading the files it wrote.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace facetool::testing {

// Runs `exe args` through the shell with its standard error in `log` (and its standard output
// discarded when `quiet`); returns the exit status, or -1 if it did not exit normally.
inline int run_cli(const std::string& exe, const std::string& args, const std::string& log, bool quiet = false) {
  const std::string command = exe + " " + args + (quiet ? " >/dev/null" : "") + " 2>" + log;
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The whole file as text ("" when it cannot be read).
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace facetool::testing
