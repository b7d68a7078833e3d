// How many output units (pixels, Winograd tiles) of one image a convolution task takes.
#pragma once

#include <algorithm>
#include <cstdint>

namespace facetool::cpu {

// Units per task when each of `batch` images has `units` of them and a task holds at most `most`
// and, where an image has enough, at least `least`, rounded up to a multiple of `multiple`
// (`most` is one): the fewest tasks per image whose count over the batch is a multiple of
// `threads` where that keeps `least` units a task, the image cut into near-equal parts. With
// parts of `most` and a rest, batch 1 left threads idle: a 48x48 output is 144 Winograd tiles,
// tasks of 128 and 16 on two threads.
inline int64_t balanced_task_units(int64_t units, int64_t batch, int64_t most, int64_t least,
                                   int64_t multiple, int64_t threads) {
  const auto ceil_div = [](int64_t a, int64_t b) { return (a + b - 1) / b; };
  int64_t tasks = ceil_div(units, most);
  while ((batch * tasks) % threads != 0 && ceil_div(units, tasks + 1) >= least) ++tasks;
  return std::min(most, ceil_div(ceil_div(units, tasks), multiple) * multiple);
}

}  // namespace facetool::cpu
