// Whether a JPEG file holds its whole image: decoders fill a cut-off file with grey silently.
#pragma once

#include <string>

namespace facetool {

// True when the JPEG at `path` reaches its end-of-image marker by walking its marker segments
// and entropy-coded scans (data after the marker, such as a phone's trailer, is allowed; an
// embedded thumbnail's marker does not count). False when the file ends first: it is truncated.
// A file that does not start like a JPEG gives true (the decoder reports it).
bool jpeg_is_complete(const std::string& path);

}  // namespace facetool
