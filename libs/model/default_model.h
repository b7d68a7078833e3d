// The model shipped with facetool: where infer, relight, pseudo-label and eval find it without --model.
#pragma once

#include <string>
#include <vector>

namespace facetool {

// File name of the shipped weights (models/ in the source tree).
inline constexpr const char* kDefaultModelFile = "facetool-v2.safetensors";

// Folders searched, in order: $FACETOOL_MODEL_DIR, then <executable>/../share/facetool/models
// (the install layout; the build tree mirrors it as build/share/facetool/models), then
// <libfacetool_core's folder>/../share/facetool/models (programs and Python modules that link
// the installed library).
std::vector<std::string> default_model_dirs();

// The shipped weights' path; throws facetool::Error naming every folder searched and what to do
// when none holds the file.
std::string default_model_path();

}  // namespace facetool
