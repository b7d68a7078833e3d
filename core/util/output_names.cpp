// unique_output_names: plain names first, then suffixed names that no input or earlier name has.
#include "core/util/output_names.h"

#include <filesystem>
#include <set>

namespace facetool {

std::vector<std::string> unique_output_names(const std::vector<std::string>& inputs,
                                             bool keep_extension) {
  namespace fs = std::filesystem;
  std::vector<std::string> stems, extensions;
  for (const std::string& input : inputs) {
    const fs::path path(input);
    stems.push_back(path.stem().string());
    extensions.push_back(keep_extension ? path.extension().string() : "");
  }
  // Every plain name is taken by its first holder; the later holders of a shared name get the
  // first free suffix, free meaning no input's plain name and no name given so far.
  std::set<std::string> taken;
  for (size_t k = 0; k < inputs.size(); ++k) taken.insert(stems[k] + extensions[k]);
  std::set<std::string> given;
  std::vector<std::string> names;
  for (size_t k = 0; k < inputs.size(); ++k) {
    const std::string plain = stems[k] + extensions[k];
    if (given.insert(plain).second) {
      names.push_back(plain);
      continue;
    }
    for (int suffix = 2;; ++suffix) {
      const std::string name = stems[k] + "_" + std::to_string(suffix) + extensions[k];
      if (taken.count(name) || given.count(name)) continue;
      given.insert(name);
      names.push_back(name);
      break;
    }
  }
  return names;
}

}  // namespace facetool
