// Shared libraries loaded at run time, and the folders facetool searches for them.
#pragma once

#include <string>
#include <vector>

namespace facetool {

// A dlopen'ed library. Never unloaded: code from it may still be referenced at exit.
class SharedLibrary {
 public:
  // Throws facetool::Error naming the file and the loader's message if it cannot be opened.
  static SharedLibrary open(const std::string& path);
  // The address of `symbol`, or nullptr if the library does not export it.
  void* symbol(const std::string& symbol) const;
  const std::string& path() const { return path_; }

 private:
  SharedLibrary(void* handle, std::string path) : handle_(handle), path_(std::move(path)) {}
  void* handle_ = nullptr;
  std::string path_;
};

// The folder holding the running executable ("" if it cannot be determined).
std::string executable_dir();
// The folder holding libfacetool_core itself ("" if it cannot be determined): backend modules are
// found relative to it, so a build tree and an installed prefix need no configured paths.
std::string core_library_dir();
// The folders searched for a module facetool loads at run time (a backend, the OpenImageIO
// module), in order, each once: those in the environment variable `env_var` (':'-separated), the
// executable's folder and its ../lib/facetool, libfacetool_core's folder and its facetool/ (an
// installed prefix's lib/facetool), so a build tree and an installed prefix need no configured paths.
std::vector<std::string> module_search_dirs(const char* env_var);
// The first of module_search_dirs(env_var) holding `file`; "" when none does, and then
// `not_found` says so, listing the places looked in and naming the variable.
std::string find_module_file(const std::string& file, const char* env_var, std::string& not_found);
// Splits a ':'-separated list such as an environment variable's value; empty parts are dropped.
std::vector<std::string> split_path_list(const std::string& list);
// Regular files in `dir` whose names end with `suffix`, sorted; empty if `dir` does not exist.
std::vector<std::string> files_with_suffix(const std::string& dir, const std::string& suffix);

}  // namespace facetool
