// Output names for a list of inputs: one per input, unique across the whole list.
#pragma once

#include <string>
#include <vector>

namespace facetool {

// One name per input, from its file name: the stem (`keep_extension` false: "x" for "a/x.png")
// or the whole file name ("x.exr"). Inputs sharing a name get "_2", "_3", ... (before the
// extension), skipping every name another input has or was given, so the names are unique
// whatever the order of the list: a/x.png, b/x.jpg, c/x_2.png give x, x_3, x_2.
std::vector<std::string> unique_output_names(const std::vector<std::string>& inputs,
                                             bool keep_extension = false);

}  // namespace facetool
