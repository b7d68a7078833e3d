// SingleProcessCommunicator: one rank; rank_rows, the slice of a global batch each rank takes.
#include <cstdlib>
#include <algorithm>
#include <iostream>

#include "libs/distributed/communicator.h"

namespace facetool {

void SingleProcessCommunicator::abort(const std::string& message) {
  std::cerr << "error: " << message << "\n";
  std::exit(1);
}

std::pair<int64_t, int64_t> rank_rows(int64_t batch, int rank, int size) {
  const int64_t base = batch / size, extra = batch % size;
  const int64_t begin = rank * base + std::min<int64_t>(rank, extra);
  return {begin, begin + base + (rank < extra ? 1 : 0)};
}

}  // namespace facetool
