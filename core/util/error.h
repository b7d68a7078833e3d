// The single exception type facetool raises, and helpers that build clear messages.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace facetool {

// Every user-facing failure is an Error whose message names the thing that failed and,
// where possible, what to do about it. Across shared-library boundaries: the C entry points of
// plugins and backend modules (plugin_api.h, backend_module.h) let no exception out (a failed
// create returns null, which the loader reports as an Error); the C++ methods of plugin and
// backend objects throw Error to their caller as ordinary C++ exceptions, which is sound because
// the loader accepts only plugins built with the program's C++ ABI and compiler family
// (FACETOOL_PLUGIN_CXX_ABI, checked at load) and Error's type information lives in
// libfacetool_core, which every plugin and module links.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
inline void append_all(std::ostringstream&) {}
template <typename T, typename... Rest>
void append_all(std::ostringstream& out, const T& first, const Rest&... rest) {
  out << first;
  append_all(out, rest...);
}
}  // namespace detail

// Builds a message from its arguments and throws facetool::Error.
template <typename... Parts>
[[noreturn]] void fail(const Parts&... parts) {
  std::ostringstream out;
  detail::append_all(out, parts...);
  throw Error(out.str());
}

// Throws facetool::Error with the message built from `parts` unless `condition` holds.
template <typename... Parts>
void check(bool condition, const Parts&... parts) {
  if (!condition) fail(parts...);
}

}  // namespace facetool
