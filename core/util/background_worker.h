// Jobs run in order on a worker thread, so that a producer overlaps its next items with them.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace facetool {

// A single worker thread that runs the submitted jobs one after another, in order. Each job
// carries a weight (e.g. the pixels of the photo it writes); submit() waits while jobs are in
// the worker (queued or running) and the new job's weight would take their total above
// `capacity`, so memory stays bounded: with the defaults (capacity 1, weight 1) at most one job
// runs while the caller prepares the next. submit() first rethrows, in the caller's thread, the
// failure of a job that ended since the last report (the new job is then not taken); finish()
// waits for every job and rethrows such a failure. A failed job does not stop the jobs behind
// it. The destructor waits for the jobs in the worker and drops any failure (call finish() to
// see it).
class BackgroundWorker {
 public:
  explicit BackgroundWorker(double capacity = 1.0);
  ~BackgroundWorker();
  BackgroundWorker(const BackgroundWorker&) = delete;
  BackgroundWorker& operator=(const BackgroundWorker&) = delete;

  void submit(std::function<void()> job, double weight = 1.0);
  void finish();
  // No job queued or running now.
  bool idle();

 private:
  void rethrow_failure();
  void run();

  const double capacity_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::pair<std::function<void()>, double>> jobs_;  // the running one first
  double weight_in_worker_ = 0.0;  // queued and running
  bool stopping_ = false;
  std::exception_ptr failure_;
  std::thread thread_;
};

}  // namespace facetool
