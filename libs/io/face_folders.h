// The per-face sub-folders of a photo's output folder (face_1/, face_2/, ...): their names, and
// the removal of those an earlier run left for faces this run did not find.
#pragma once

#include <string>

namespace facetool {

// "<folder>/face_<k>".
std::string face_folder_name(const std::string& folder, int k);

// Removes <folder>/face_<k>/ for k = first, first + 1, ... while such a folder exists: the
// results of an earlier run of the same photo that found more faces (this run's files list
// its own faces).
void remove_stale_face_folders(const std::string& folder, int first);

}  // namespace facetool
