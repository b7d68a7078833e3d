// SharedLibrary and search-path helpers (POSIX dlopen).
#include "core/util/shared_library.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "core/util/elf_check.h"
#include "core/util/error.h"

namespace facetool {

SharedLibrary SharedLibrary::open(const std::string& path) {
  check(std::filesystem::exists(path), "cannot load '", path, "': no such file");
  check_loadable_elf_file(path);  // a truncated library would crash dlopen (SIGBUS)
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    fail("cannot load '", path, "': ", why ? why : "unknown dynamic loader error");
  }
  return SharedLibrary(handle, path);
}

void* SharedLibrary::symbol(const std::string& symbol) const {
  return dlsym(handle_, symbol.c_str());
}

std::string executable_dir() {
  std::error_code ec;
  auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  return exe.parent_path().string();
}

std::string core_library_dir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&core_library_dir), &info) == 0 || !info.dli_fname) return "";
  std::error_code ec;
  const auto path = std::filesystem::canonical(info.dli_fname, ec);
  if (ec) return "";
  return path.parent_path().string();
}

std::vector<std::string> module_search_dirs(const char* env_var) {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv(env_var))
    for (auto& d : split_path_list(env)) dirs.push_back(d);
  const std::string exe = executable_dir();
  if (!exe.empty()) {
    dirs.push_back(exe);
    dirs.push_back(exe + "/../lib/facetool");
  }
  const std::string core = core_library_dir();
  if (!core.empty()) {
    dirs.push_back(core);
    dirs.push_back(core + "/facetool");
  }
  // The same folder reached twice (the variable pointing beside the executable) once.
  std::vector<std::string> unique;
  for (const std::string& d : dirs) {
    std::error_code ec;
    const std::string canonical = std::filesystem::weakly_canonical(d, ec).string();
    const std::string key = ec ? d : canonical;
    if (std::find(unique.begin(), unique.end(), key) == unique.end()) unique.push_back(key);
  }
  return unique;
}

std::string find_module_file(const std::string& file, const char* env_var, std::string& not_found) {
  std::string tried;
  for (const std::string& dir : module_search_dirs(env_var)) {
    const std::string path = dir + "/" + file;
    if (std::filesystem::exists(path)) return path;
    tried += "\n  " + path;
  }
  not_found = "module " + file + " not found; looked in:" + tried + "\n  set " + env_var +
              " to the folder holding it";
  return "";
}

std::vector<std::string> split_path_list(const std::string& list) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (start <= list.size()) {
    size_t end = list.find(':', start);
    if (end == std::string::npos) end = list.size();
    if (end > start) parts.push_back(list.substr(start, end - start));
    start = end + 1;
  }
  return parts;
}

std::vector<std::string> files_with_suffix(const std::string& dir, const std::string& suffix) {
  std::vector<std::string> found;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return found;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file(ec) && name.size() >= suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      found.push_back(entry.path().string());
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace facetool
