// Checks of JSON text that the parser itself does not make: a key given twice in one object.
#pragma once

#include <string>

namespace facetool {

// The first key that appears twice in one object of `text` ("" when none, or when the text does
// not parse: the caller's own parse reports that). JSON parsers keep the last of two equal keys
// silently; facetool's configuration and light files refuse them.
std::string first_duplicate_json_key(const std::string& text);

}  // namespace facetool
