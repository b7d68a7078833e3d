// DetectionSummary: counts per folder and the lines that report them.
#include "libs/face/detection_summary.h"

#include <filesystem>

namespace facetool {

void DetectionSummary::add(const std::string& photo_path, int faces, const std::string& reason) {
  std::string folder = std::filesystem::path(photo_path).parent_path().string();
  if (folder.empty()) folder = ".";
  auto it = folders_.find(folder);
  if (it == folders_.end()) {
    order_.push_back(folder);
    it = folders_.emplace(folder, Folder{}).first;
  }
  Folder& f = it->second;
  ++f.photos;
  f.faces += faces;
  if (faces == 0) {
    ++f.without;
    const std::string why = reason.empty() ? "no face found" : reason;
    ++f.reasons[why];
    f.missed.push_back(std::filesystem::path(photo_path).filename().string() + ": " + why);
  }
}

void DetectionSummary::print(std::ostream& out, int list) const {
  for (const std::string& name : order_) {
    const Folder& f = folders_.at(name);
    out << name << ": " << f.photos << " photo" << (f.photos == 1 ? "" : "s") << ", " << f.faces
        << " face" << (f.faces == 1 ? "" : "s") << ", " << f.without << " without a face";
    if (f.without > 0) {
      out << " (";
      bool first = true;
      for (const auto& [reason, count] : f.reasons) {
        out << (first ? "" : ", ") << count << " " << reason;
        first = false;
      }
      out << ")";
    }
    out << "\n";
    for (int i = 0; i < static_cast<int>(f.missed.size()) && i < list; ++i)
      out << "  " << f.missed[i] << "\n";
    if (static_cast<int>(f.missed.size()) > list)
      out << "  ... and " << f.missed.size() - list << " more\n";
  }
}

int DetectionSummary::photos() const {
  int n = 0;
  for (const auto& [name, f] : folders_) n += f.photos;
  return n;
}

int DetectionSummary::photos_without_face() const {
  int n = 0;
  for (const auto& [name, f] : folders_) n += f.without;
  return n;
}

}  // namespace facetool
