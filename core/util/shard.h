// Shards of a job's input list (--shard i/n, e.g. Slurm array jobs): parsing and the items one shard takes.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace facetool {

// Parses "i/n" (0 <= i < n); throws facetool::Error otherwise.
void parse_shard(const std::string& text, int& index, int& count);

// The positions i, i+n, i+2n, ... of a list of `total` items that shard i of n takes, in order.
std::vector<size_t> shard_positions(size_t total, int index, int count);

}  // namespace facetool
