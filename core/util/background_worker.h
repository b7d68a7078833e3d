// One job at a time on a worker thread, so that a producer overlaps its next item with it.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace facetool {

// A single worker thread that runs the submitted jobs one after another. submit() waits until
// the previous job has finished (so at most one job runs and one item is being prepared: memory
// stays bounded), rethrows that job's exception in the caller's thread, then hands over the new
// job. finish() waits for the last job and rethrows its exception. The destructor waits for a
// running job and drops any exception (call finish() to see it).
class BackgroundWorker {
 public:
  BackgroundWorker();
  ~BackgroundWorker();
  BackgroundWorker(const BackgroundWorker&) = delete;
  BackgroundWorker& operator=(const BackgroundWorker&) = delete;

  void submit(std::function<void()> job);
  void finish();

 private:
  void wait_idle_and_rethrow(std::unique_lock<std::mutex>& lock);
  void run();

  std::mutex mutex_;
  std::condition_variable changed_;
  std::function<void()> job_;
  bool busy_ = false, stopping_ = false;
  std::exception_ptr failure_;
  std::thread thread_;
};

}  // namespace facetool
