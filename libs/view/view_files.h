// Writing the view pages of an infer run: view.html in each photo's folder, index.html beside them.
#pragma once

#include <string>
#include <vector>

#include "libs/view/view_inputs.h"

namespace facetool::view {

// Writes <folder>/view.html for each of `folders` (photo folders of infer runs), each offering the
// lights of the others as presets, and, when `index_path` is not empty, an index page there linking
// them. A folder that cannot be shown gets a line on stderr naming it and why; the others are
// written. Every file is written atomically. Returns the number of folders that failed.
int write_view_pages(const std::vector<std::string>& folders, const std::string& index_path,
                     const ViewOptions& options);

// The photo folders of `path`: itself when it holds faces.json, else its sub-folders that do
// (sorted). Throws facetool::Error naming `path` when it is neither.
std::vector<std::string> photo_folders(const std::string& path);

}  // namespace facetool::view
