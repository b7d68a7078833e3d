// available_memory_bytes from /proc/meminfo and getrlimit(RLIMIT_AS), /proc/self/statm.
#include "core/util/memory_budget.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace facetool {
namespace {

// MemAvailable of /proc/meminfo in bytes, or UINT64_MAX.
uint64_t system_available() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kilobytes = 0;
  std::string unit;
  while (in >> key >> kilobytes >> unit)
    if (key == "MemAvailable:") return kilobytes * 1024;
  return std::numeric_limits<uint64_t>::max();
}

// Bytes the address-space limit still allows this process to map, or UINT64_MAX.
uint64_t address_space_left() {
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY)
    return std::numeric_limits<uint64_t>::max();
  std::ifstream in("/proc/self/statm");
  uint64_t pages = 0;
  if (!(in >> pages)) return std::numeric_limits<uint64_t>::max();
  const uint64_t used = pages * static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
  return used >= limit.rlim_cur ? 0 : limit.rlim_cur - used;
}

}  // namespace

uint64_t available_memory_bytes() {
  const uint64_t a = system_available(), b = address_space_left();
  return a < b ? a : b;
}

std::string format_gigabytes(uint64_t bytes) {
  char text[32];
  const double gb = static_cast<double>(bytes) / (1024.0 * 1024.0 * 1024.0);
  std::snprintf(text, sizeof text, gb < 0.1 ? "%.2f GB" : "%.1f GB", gb);
  return text;
}

OutOfMemory out_of_memory(const std::string& what, uint64_t bytes) {
  std::ostringstream message;
  message << "out of memory while " << what;
  if (bytes > 0) message << " (needs ~" << format_gigabytes(bytes) << ")";
  const uint64_t available = available_memory_bytes();
  if (available != std::numeric_limits<uint64_t>::max())
    message << "; about " << format_gigabytes(available) << " available";
  message << ": close other programs, raise the memory limit (ulimit -v) or use a smaller input";
  return OutOfMemory(message.str());
}

void check_memory_budget(uint64_t bytes, const std::string& what) {
  const uint64_t available = available_memory_bytes();
  if (bytes > available) throw out_of_memory(what, bytes);
}

}  // namespace facetool
