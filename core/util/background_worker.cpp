// BackgroundWorker: a worker thread, a queue of weighted jobs and the first unreported failure.
#include "core/util/background_worker.h"

namespace facetool {

BackgroundWorker::BackgroundWorker(double capacity) : capacity_(capacity), thread_([this] { run(); }) {}

BackgroundWorker::~BackgroundWorker() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [this] { return jobs_.empty(); });
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void BackgroundWorker::rethrow_failure() {
  if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
}

void BackgroundWorker::submit(std::function<void()> job, double weight) {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    // Wait for room (an empty worker always has room), or for a failure to report.
    changed_.wait(lock, [&] { return failure_ || jobs_.empty() || weight_in_worker_ + weight <= capacity_; });
    rethrow_failure();
    jobs_.emplace_back(std::move(job), weight);
    weight_in_worker_ += weight;
  }
  changed_.notify_all();
}

void BackgroundWorker::finish() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return jobs_.empty(); });
  rethrow_failure();
}

bool BackgroundWorker::idle() {
  std::lock_guard<std::mutex> lock(mutex_);
  return jobs_.empty();
}

void BackgroundWorker::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return !jobs_.empty() || stopping_; });
    if (jobs_.empty()) return;  // stopping with nothing to do
    std::function<void()> job = std::move(jobs_.front().first);
    lock.unlock();
    std::exception_ptr failure;
    try {
      job();
    } catch (...) {
      failure = std::current_exception();
    }
    job = nullptr;  // release what the job held before room is made for the next one
    lock.lock();
    if (failure && !failure_) failure_ = failure;
    weight_in_worker_ -= jobs_.front().second;
    jobs_.pop_front();
    changed_.notify_all();
  }
}

}  // namespace facetool
