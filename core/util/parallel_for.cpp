// parallel_for: a persistent pool of worker threads that claim chunks of a range dynamically.
#include "core/util/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace facetool {
namespace {

thread_local int tls_slot = 0;
thread_local bool tls_inside_parallel = false;

// How long a thread that waits for the pool (a worker for the next job, the caller for the
// workers to finish) keeps checking before it sleeps on a condition variable: a network's
// forward pass at batch 1 runs about a hundred short jobs, microseconds apart, and a sleep and a
// wake-up cost each of them a context switch and tens of microseconds of latency
// (docs/backends.md, "Threads"). FACETOOL_SPIN_US (0 to 100000; 0: sleep at once), default 50.
std::chrono::microseconds configured_spin() {
  if (const char* env = std::getenv("FACETOOL_SPIN_US")) {
    const long us = std::atol(env);
    if (us >= 0) return std::chrono::microseconds(std::min(us, 100000L));
  }
  return std::chrono::microseconds(50);
}

// Checks `ready` until it holds or `spin` has passed; true if it held.
template <typename Ready>
bool spin_until(Ready ready, std::chrono::microseconds spin) {
  if (spin.count() == 0) return ready();
  const auto deadline = std::chrono::steady_clock::now() + spin;
  for (int i = 0;; ++i) {
    if (ready()) return true;
    if ((i & 63) == 63 && std::chrono::steady_clock::now() >= deadline) return false;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }
}

int configured_thread_count() {
  if (const char* env = std::getenv("FACETOOL_NUM_THREADS")) {
    const int n = std::atoi(env);
    if (n > 0) return std::min(n, 256);
  }
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(std::min(hw, 256u));
}

// One parallel_for call in flight: workers and the caller claim chunk indices from `next`.
struct Job {
  const std::function<void(int64_t, int64_t)>* fn = nullptr;
  int64_t n = 0;
  int64_t chunk = 1;
  int64_t chunks = 0;
  std::atomic<int64_t> next{0};
  std::atomic<int64_t> done{0};
  std::exception_ptr error;
  std::mutex error_mutex;

  void run_chunks() {
    for (;;) {
      const int64_t c = next.fetch_add(1);
      if (c >= chunks) return;
      const int64_t begin = c * chunk;
      const int64_t end = std::min(n, begin + chunk);
      try {
        (*fn)(begin, end);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
      done.fetch_add(1);
    }
  }
};

class ThreadPool {
 public:
  // A thread the system cannot give (ulimit -v, a process limit) is done without: the pool runs
  // with the threads it got instead of ending the process (a joinable thread left in workers_ by
  // an exception would call std::terminate).
  explicit ThreadPool(int threads) : threads_(1), spin_(configured_spin()) {
    for (int i = 1; i < threads; ++i) {
      try {
        workers_.emplace_back([this, i] { worker_loop(i); });
      } catch (const std::system_error&) {
        break;
      }
      threads_ = i + 1;
    }
  }
  ~ThreadPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
  }

  int threads() const { return threads_; }

  void run(Job& job) {
    std::lock_guard<std::mutex> serial(run_mutex_);  // one job at a time
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = &job;
      ++generation_;
    }
    wake_.notify_all();
    tls_inside_parallel = true;
    job.run_chunks();
    tls_inside_parallel = false;
    spin_until([&] { return job.done.load() == job.chunks && busy_workers_.load() == 0; }, spin_);
    std::unique_lock<std::mutex> lock(mutex_);
    finished_.wait(lock, [&] { return job.done.load() == job.chunks && busy_workers_ == 0; });
    job_ = nullptr;
  }

 private:
  void worker_loop(int slot) {
    tls_slot = slot;
    tls_inside_parallel = true;
    uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      if (!stopping_ && generation_ == seen) {  // the next job usually comes within microseconds
        lock.unlock();
        spin_until([&] { return generation_.load() != seen || stopping_.load(); }, spin_);
        lock.lock();
      }
      wake_.wait(lock, [&] { return stopping_ || (job_ != nullptr && generation_ != seen); });
      if (stopping_) return;
      seen = generation_;
      Job* job = job_;
      ++busy_workers_;
      lock.unlock();
      job->run_chunks();
      lock.lock();
      --busy_workers_;
      finished_.notify_all();
    }
  }

  int threads_;
  const std::chrono::microseconds spin_;
  std::vector<std::thread> workers_;
  std::mutex run_mutex_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable finished_;
  // Written under mutex_; atomic so that the spinning threads may read them without it.
  Job* job_ = nullptr;
  std::atomic<uint64_t> generation_{0};
  std::atomic<int> busy_workers_{0};
  std::atomic<bool> stopping_{false};
};

ThreadPool& pool() {
  static ThreadPool* p = new ThreadPool(configured_thread_count());  // lives until exit
  return *p;
}

}  // namespace

int parallel_thread_count() { return pool().threads(); }

int parallel_thread_slot() { return tls_slot; }

int parallel_threads_here() { return tls_inside_parallel ? 1 : parallel_thread_count(); }

InlineParallelScope::InlineParallelScope() : was_inline_(tls_inside_parallel) { tls_inside_parallel = true; }

InlineParallelScope::~InlineParallelScope() { tls_inside_parallel = was_inline_; }

void parallel_for(int64_t n, int64_t grain, const std::function<void(int64_t, int64_t)>& fn) {
  if (n <= 0) return;
  grain = std::max<int64_t>(grain, 1);
  ThreadPool& p = pool();
  if (p.threads() == 1 || n <= grain || tls_inside_parallel) {
    fn(0, n);
    return;
  }
  // About four chunks per thread for load balance, never smaller than `grain`.
  const int64_t target_chunks = static_cast<int64_t>(p.threads()) * 4;
  Job job;
  job.fn = &fn;
  job.n = n;
  job.chunk = std::max(grain, (n + target_chunks - 1) / target_chunks);
  job.chunks = (n + job.chunk - 1) / job.chunk;
  p.run(job);
  if (job.error) std::rethrow_exception(job.error);
}

void parallel_for_each_item(int64_t n, const std::function<void(int64_t)>& fn) {
  if (n <= 0) return;
  std::atomic<int64_t> next{0};
  std::atomic<bool> failed{false};
  // One chunk per thread; each claims items until none are left or one has failed.
  parallel_for(std::min<int64_t>(n, parallel_thread_count()), 1, [&](int64_t, int64_t) {
    for (int64_t i = next++; i < n && !failed.load(); i = next++) {
      try {
        fn(i);
      } catch (...) {
        failed = true;
        throw;
      }
    }
  });
}

}  // namespace facetool
