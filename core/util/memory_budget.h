// Memory budgets: an allocation sized from a file's header is checked against what the machine
// (and ulimit -v) can give before it is made, and an exhausted allocation is named.
#pragma once

#include <cstdint>
#include <new>
#include <string>

#include "core/util/error.h"

namespace facetool {

// Out of memory: a facetool::Error whose message says "out of memory while <what> (needs ~N GB
// ...)". Folder runs catch it to go on with the next photo.
class OutOfMemory : public Error {
 public:
  using Error::Error;
};

// Bytes this process can still allocate: the smaller of the memory the system reports available
// (MemAvailable) and what the address-space limit (ulimit -v) leaves; UINT64_MAX when unknown.
uint64_t available_memory_bytes();

// "1.3 GB" style figure for messages.
std::string format_gigabytes(uint64_t bytes);

// Throws OutOfMemory "out of memory while <what> (needs ~N GB, about M GB available); ..." when
// `bytes` exceed available_memory_bytes().
void check_memory_budget(uint64_t bytes, const std::string& what);

// The OutOfMemory error for a failed allocation of about `bytes` (0: unknown) while `what`.
OutOfMemory out_of_memory(const std::string& what, uint64_t bytes);

// Runs `fn` and returns what it returns; an allocation failing inside (std::bad_alloc, or the
// OutOfMemory of a lower level such as a backend's allocator, which knows only its own block)
// comes out as out_of_memory(what, bytes): the task that needed the memory and about how much
// all of it takes (`bytes`, the caller's estimate).
template <typename Fn>
decltype(auto) naming_out_of_memory(const std::string& what, uint64_t bytes, Fn&& fn) {
  try {
    return fn();
  } catch (const std::bad_alloc&) {
    throw out_of_memory(what, bytes);
  } catch (const OutOfMemory&) {
    throw out_of_memory(what, bytes);
  }
}

}  // namespace facetool
