// The view pages of an infer run written to disk, and the photo folders found under a path.
#include "libs/view/view_files.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "core/util/atomic_file.h"
#include "core/util/error.h"
#include "core/util/file_checks.h"
#include "libs/view/view_page.h"
#include "libs/view/view_presets.h"

namespace fs = std::filesystem;

namespace facetool::view {
namespace {

// The best face's light of each folder that has one (faces.json only), as a preset.
std::vector<LightPreset> run_lights(const std::vector<std::string>& folders) {
  std::vector<LightPreset> out;
  for (const std::string& folder : folders) {
    try {
      const nlohmann::json json = nlohmann::json::parse(
          read_regular_input_file((fs::path(folder) / "faces.json").string(), kMaxTextFileBytes, "faces.json"));
      const nlohmann::json& light = json.at("faces").at(0).at("light_photo_frame");
      if (!light.is_array() || light.size() != 27) continue;
      LightPreset preset;
      preset.name = "light of " + fs::path(folder).lexically_normal().filename().string();
      for (int i = 0; i < 27; ++i) preset.light[i] = light.at(i).get<double>();
      out.push_back(preset);
    } catch (const std::exception&) {
      // Reported when the folder's own page is made.
    }
  }
  return out;
}

void write_text(const std::string& path, const std::string& text) { write_file_atomically(path, text.data(), text.size()); }

// The page's address relative to the index, each byte outside [A-Za-z0-9-._~/] percent-encoded.
std::string relative_url(const fs::path& page, const fs::path& index_folder) {
  const std::string relative = fs::absolute(page).lexically_normal().lexically_relative(
      fs::absolute(index_folder).lexically_normal()).generic_string();
  static const char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : relative) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> photo_folders(const std::string& path) {
  check_input_folder(path, "view");
  if (fs::exists(fs::path(path) / "faces.json")) return {path};
  std::vector<std::string> out;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(path, ec))
    if (entry.is_directory() && fs::exists(entry.path() / "faces.json")) out.push_back(entry.path().string());
  check(!ec, "cannot list '", path, "': ", ec.message());
  check(!out.empty(), "'", path, "' is not an output of `facetool infer`: it holds no faces.json, nor does any folder "
        "in it; give infer's output folder (-o DIR) or one photo's folder in it");
  std::sort(out.begin(), out.end());
  return out;
}

int write_view_pages(const std::vector<std::string>& folders, const std::string& index_path, const ViewOptions& options) {
  const std::vector<LightPreset> lights = run_lights(folders);
  std::vector<IndexEntry> entries;
  int failed = 0;
  for (const std::string& folder : folders) {
    try {
      const ViewPhoto photo = read_view_photo(folder, options);
      if (photo.mask_mismatch > 1e-3)
        std::cerr << "view: " << folder << ": the page's paste-back mask differs from infer's by up to "
                  << photo.mask_mismatch << " (coverage)"
                  << (photo.mask_recorded ? "; the folder's files do not agree, run infer again\n"
                                          : "; give view the --feather and --face-region infer was run with\n");
      const fs::path page = fs::path(folder) / "view.html";
      write_text(page.string(), view_page_html(photo, page_presets(photo, lights)));
      if (!index_path.empty())
        entries.push_back({photo.name, relative_url(page, fs::path(index_path).parent_path()), thumbnail_png(photo, 160)});
    } catch (const Error& e) {
      std::cerr << "view: " << e.what() << "\n";
      ++failed;
    }
  }
  if (!index_path.empty() && !entries.empty()) write_text(index_path, index_page_html(entries));
  return failed;
}

}  // namespace facetool::view
