// The model shipped with facetool: where infer, relight, pseudo-label and eval find it without --model.
#include "libs/model/default_model.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "core/util/error.h"
#include "core/util/shared_library.h"

namespace facetool {

std::vector<std::string> default_model_dirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("FACETOOL_MODEL_DIR"); env && *env) dirs.emplace_back(env);
  for (const std::string& base : {executable_dir(), core_library_dir()}) {
    if (base.empty()) continue;
    const std::string dir =
        (std::filesystem::path(base) / ".." / "share" / "facetool" / "models").lexically_normal().string();
    if (std::find(dirs.begin(), dirs.end(), dir) == dirs.end()) dirs.push_back(dir);
  }
  return dirs;
}

std::string default_model_path() {
  std::string searched;
  for (const std::string& dir : default_model_dirs()) {
    const std::filesystem::path path = std::filesystem::path(dir) / kDefaultModelFile;
    std::error_code ec;
    if (std::filesystem::is_regular_file(path, ec)) return path.string();
    searched += (searched.empty() ? "" : ", ") + dir;
  }
  throw Error(std::string("no --model given and the shipped model ") + kDefaultModelFile +
              " is not in " + (searched.empty() ? std::string("any folder") : searched) +
              "; pass --model WEIGHTS, set FACETOOL_MODEL_DIR, or rebuild (the build copies "
              "models/ beside the program)");
}

}  // namespace facetool
