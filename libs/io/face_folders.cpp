// The per-face sub-folders of a photo's output folder, and the removal of stale ones.
#include "libs/io/face_folders.h"

#include <filesystem>

namespace facetool {

std::string face_folder_name(const std::string& folder, int k) {
  return (std::filesystem::path(folder) / ("face_" + std::to_string(k))).string();
}

void remove_stale_face_folders(const std::string& folder, int first) {
  for (int k = first;; ++k) {
    std::error_code ec;
    const std::filesystem::path stale = face_folder_name(folder, k);
    if (!std::filesystem::is_directory(stale, ec)) break;
    std::filesystem::remove_all(stale, ec);
  }
}

}  // namespace facetool
