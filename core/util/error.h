// The single exception type facetool raises, and helpers that build clear messages.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace facetool {

// Every user-facing failure is an Error whose message names the thing that failed and,
// where possible, what to do about it. Plugin and backend boundaries convert to/from it.
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
