// The thread pool under parallel_for: every index of every call run exactly once, over many
// short calls back to back and calls far apart (workers that spin, then sleep, and are woken);
// the first exception reaches the caller; nested calls and calls in an InlineParallelScope run
// inline; parallel_for_each_item hands
// out items one at a time and ends at a failure. CTest runs it again with
// FACETOOL_SPIN_US=0 (sleep at once) and with a spin longer than any gap.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/util/parallel_for.h"

namespace facetool {
namespace {

// `calls` parallel_for calls of sizes 2..201, pausing `gap` between calls, each chunk busy for
// `work` (so that a worker woken from its sleep still finds chunks left); every index's counter
// must end at the number of calls that covered it.
void run_calls(int calls, std::chrono::microseconds gap, std::chrono::microseconds work) {
  std::vector<std::atomic<int>> counts(201);
  std::vector<int> expected(201, 0);
  std::mutex mutex;
  std::set<std::thread::id> threads;
  for (int k = 0; k < calls; ++k) {
    const int64_t n = 2 + (k * 37) % 200;
    for (int64_t i = 0; i < n; ++i) ++expected[i];
    parallel_for(n, 1, [&](int64_t begin, int64_t end) {
      for (int64_t i = begin; i < end; ++i) ++counts[i];
      const auto until = std::chrono::steady_clock::now() + work;
      while (std::chrono::steady_clock::now() < until) {
      }
      std::lock_guard<std::mutex> lock(mutex);
      threads.insert(std::this_thread::get_id());
    });
    if (gap.count()) std::this_thread::sleep_for(gap);
  }
  for (size_t i = 0; i < counts.size(); ++i) ASSERT_EQ(counts[i].load(), expected[i]) << "index " << i;
  // Which threads took chunks depends on the scheduler, so it is reported, not asserted.
  std::printf("%d calls: chunks run by %zu of %d threads\n", calls, threads.size(), parallel_thread_count());
}

TEST(ParallelFor, ManyShortCallsBackToBackRunEveryIndexOnce) {
  run_calls(20000, std::chrono::microseconds(0), std::chrono::microseconds(0));
}

TEST(ParallelFor, CallsFarApartRunEveryIndexOnce) {
  run_calls(100, std::chrono::microseconds(300), std::chrono::microseconds(200));
}

TEST(ParallelFor, TheFirstExceptionReachesTheCallerAfterEveryChunk) {
  std::atomic<int> ran{0};
  EXPECT_THROW(parallel_for(64, 1,
                            [&](int64_t begin, int64_t end) {
                              ran += static_cast<int>(end - begin);
                              if (begin == 0) throw std::runtime_error("chunk 0");
                            }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 64);
  // The pool still works afterwards.
  std::atomic<int> sum{0};
  parallel_for(100, 1, [&](int64_t begin, int64_t end) { sum += static_cast<int>(end - begin); });
  EXPECT_EQ(sum.load(), 100);
}

// Item 0 waits until every other item has run: that ends only if the other threads take items
// one at a time while it waits (parallel_for's fixed chunks would hold items 1-4 behind it). No
// timing decides the outcome; the 60 s limit only turns a hang into a failure.
TEST(ParallelForEachItem, RunsEveryItemOnceAndNoItemWaitsBehindALongOne) {
  if (parallel_thread_count() < 2) GTEST_SKIP() << "one thread: nothing runs beside item 0";
  constexpr int kItems = 40;
  std::vector<std::atomic<int>> runs(kItems);
  std::atomic<int> others_done{0};
  std::atomic<bool> waited_out{false};
  parallel_for_each_item(kItems, [&](int64_t i) {
    ++runs[static_cast<size_t>(i)];
    if (i != 0) {
      ++others_done;
      return;
    }
    const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (others_done.load() < kItems - 1)
      if (std::chrono::steady_clock::now() > limit) {
        waited_out = true;
        return;
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
  });
  EXPECT_FALSE(waited_out.load()) << "the other items stayed behind item 0";
  for (int i = 0; i < kItems; ++i) EXPECT_EQ(runs[static_cast<size_t>(i)].load(), 1) << "item " << i;
}

// How many items other threads start after a failure depends on the scheduler, so it is not
// asserted; that the loop ends at the failing item is, where it runs inline.
TEST(ParallelForEachItem, AFailureReachesTheCallerAndEndsTheLoop) {
  constexpr int kItems = 1000;
  auto run = [](std::atomic<int>& started) {
    try {
      parallel_for_each_item(kItems, [&](int64_t i) {
        ++started;
        if (i == 3) throw std::runtime_error("item 3");
      });
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 3");
    }
  };
  // On the pool's threads: the first error reaches the caller, and the pool works afterwards.
  std::atomic<int> threaded{0};
  run(threaded);
  std::atomic<int> sum{0};
  parallel_for(100, 1, [&](int64_t begin, int64_t end) { sum += static_cast<int>(end - begin); });
  EXPECT_EQ(sum.load(), 100);
  // Inline (inside a parallel_for, so on one thread in order): items 0-3, then the error.
  std::atomic<int> inline_started{0};
  parallel_for(2, 1, [&](int64_t begin, int64_t) {
    if (begin == 0) run(inline_started);
  });
  EXPECT_EQ(inline_started.load(), 4);
}

TEST(ParallelFor, NestedCallsRunInlineOnTheCallingThread) {
  std::atomic<int> mismatched{0}, total{0};
  parallel_for(8, 1, [&](int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i) {
      const std::thread::id outer = std::this_thread::get_id();
      parallel_for(16, 1, [&](int64_t b, int64_t e) {
        if (std::this_thread::get_id() != outer) ++mismatched;
        total += static_cast<int>(e - b);
      });
    }
  });
  EXPECT_EQ(mismatched.load(), 0);
  EXPECT_EQ(total.load(), 8 * 16);
}

// What a call here would run on: the pool outside, one thread inside a call or an inline scope.
TEST(ParallelFor, ThreadsHereAreOneWhereCallsRunInline) {
  EXPECT_EQ(parallel_threads_here(), parallel_thread_count());
  std::atomic<int> inside_not_one{0};
  parallel_for(8, 1, [&](int64_t, int64_t) {
    if (parallel_threads_here() != 1) ++inside_not_one;
  });
  EXPECT_EQ(inside_not_one.load(), 0);
  {
    InlineParallelScope here;
    EXPECT_EQ(parallel_threads_here(), 1);
  }
  EXPECT_EQ(parallel_threads_here(), parallel_thread_count());
}

// Calls [0, n) in chunks, recording which threads ran them; returns how many chunks there were.
int chunks_of(int64_t n, std::set<std::thread::id>& threads) {
  std::mutex mutex;
  int chunks = 0;
  parallel_for(n, 1, [&](int64_t, int64_t) {
    std::lock_guard<std::mutex> lock(mutex);
    threads.insert(std::this_thread::get_id());
    ++chunks;
  });
  return chunks;
}

TEST(ParallelFor, AnInlineScopeRunsItsThreadsCallsAloneAndEndsWithIt) {
  if (parallel_thread_count() < 2) GTEST_SKIP() << "one thread: every call runs inline anyway";
  std::set<std::thread::id> threads;
  {
    InlineParallelScope here;
    EXPECT_EQ(chunks_of(1000, threads), 1);  // one call of the whole range
    {
      InlineParallelScope nested;
      EXPECT_EQ(chunks_of(1000, threads), 1);
    }
    EXPECT_EQ(chunks_of(1000, threads), 1);  // the inner scope's end keeps the outer one's
  }
  EXPECT_EQ(threads, std::set<std::thread::id>{std::this_thread::get_id()});
  // Another thread's calls, meanwhile, still use the pool: a scope is one thread's.
  std::set<std::thread::id> other;
  int other_chunks = 0;
  {
    InlineParallelScope here;
    std::thread([&] { other_chunks = chunks_of(1000, other); }).join();
  }
  EXPECT_GT(other_chunks, 1);
  EXPECT_GT(chunks_of(1000, threads), 1);  // after the scope, chunks again
}

}  // namespace
}  // namespace facetool
