// DetectionSummary: per folder of photos, how many were read, how many faces were found and which
// photos had none, with the reason where one is known (the --report line of infer and detect).
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace facetool {

class DetectionSummary {
 public:
  // One photo: `faces` found (0: none), `reason` why none when known ("" otherwise).
  void add(const std::string& photo_path, int faces, const std::string& reason = "");
  // One line per folder, in first-seen order: "FOLDER: P photos, F faces, N without a face
  // (k unreadable, ...)", then up to `list` photos without a face with their reasons.
  void print(std::ostream& out, int list = 10) const;
  int photos() const;
  int photos_without_face() const;

 private:
  struct Folder {
    int photos = 0, faces = 0, without = 0;
    std::map<std::string, int> reasons;
    std::vector<std::string> missed;  // "photo: reason"
  };
  std::vector<std::string> order_;
  std::map<std::string, Folder> folders_;
};

}  // namespace facetool
