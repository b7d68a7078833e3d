// Base64 (RFC 4648, with padding) for the data URLs and packed arrays of the view page.
#pragma once

#include <cstddef>
#include <string>

namespace facetool::view {

std::string base64_encode(const unsigned char* data, size_t size);

}  // namespace facetool::view
