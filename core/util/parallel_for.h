// A small persistent thread pool and parallel_for over index ranges.
#pragma once

#include <cstdint>
#include <functional>

namespace facetool {

// Number of threads parallel_for uses (the calling thread included): FACETOOL_NUM_THREADS when
// set to a positive number, otherwise std::thread::hardware_concurrency().
int parallel_thread_count();

// The threads a parallel_for called here would run on: 1 where it runs inline (inside another
// parallel_for, in an InlineParallelScope, or with one thread), else parallel_thread_count().
// For work split into as many parts as threads (a batch-1 layer run whole on one thread).
int parallel_threads_here();

// Which of the parallel_for threads is running the caller: 0 for the calling (outside) thread,
// 1 .. parallel_thread_count()-1 for pool workers. Useful for per-thread scratch buffers.
int parallel_thread_slot();

// Runs fn(begin, end) over disjoint chunks covering [0, n), each at least `grain` items long
// (except possibly the last), on the pool's threads and the calling thread; returns when all are
// done. Runs inline when n is small, when there is one thread, or when called from inside
// another parallel_for. The first exception thrown by fn is rethrown here after all chunks end.
void parallel_for(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& fn);

// While one lives, parallel_for and parallel_for_each_item called on its thread run inline, on
// that thread alone: for work beside a parallel computation on another thread (infer's writer
// pasting faces back while the network runs), which then keeps the pool to itself. Scopes nest.
class InlineParallelScope {
 public:
  InlineParallelScope();
  ~InlineParallelScope();
  InlineParallelScope(const InlineParallelScope&) = delete;
  InlineParallelScope& operator=(const InlineParallelScope&) = delete;

 private:
  bool was_inline_;
};

// Runs fn(i) for every i in [0, n) on the pool's threads, each thread taking the next item when
// it is done with one: for long, independent items (files), where parallel_for's fixed chunks
// would leave a thread idle at the end. After an exception no further item starts; the first
// exception is rethrown once the items already running end. Inline where parallel_for is.
void parallel_for_each_item(int64_t n, const std::function<void(int64_t)>& fn);

}  // namespace facetool
