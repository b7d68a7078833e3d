// Shards of a job's input list: "i/n" parsing and the positions shard i takes.
#include "core/util/shard.h"

#include <exception>

#include "core/util/error.h"

namespace facetool {

void parse_shard(const std::string& text, int& index, int& count) {
  const size_t slash = text.find('/');
  bool ok = slash != std::string::npos && slash > 0 && slash + 1 < text.size();
  if (ok) {
    try {
      size_t used_i = 0, used_n = 0;
      index = std::stoi(text.substr(0, slash), &used_i);
      count = std::stoi(text.substr(slash + 1), &used_n);
      ok = used_i == slash && used_n == text.size() - slash - 1 && count > 0 && index >= 0 &&
           index < count;
    } catch (const std::exception&) {
      ok = false;
    }
  }
  check(ok, "--shard '", text, "' is not i/n with 0 <= i < n (e.g. 0/4 ... 3/4)");
}

std::vector<size_t> shard_positions(size_t total, int index, int count) {
  check(count > 0 && index >= 0 && index < count, "shard ", index, "/", count, " is not i/n with 0 <= i < n");
  std::vector<size_t> positions;
  for (size_t k = static_cast<size_t>(index); k < total; k += static_cast<size_t>(count)) positions.push_back(k);
  return positions;
}

}  // namespace facetool
