// BackgroundWorker: jobs run one at a time, in order, off the caller's thread; submit() waits
// only while the jobs in the worker would weigh more than its capacity; a job's failure reaches
// the caller at the next submit() or at finish().
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/util/background_worker.h"

namespace facetool {
namespace {

TEST(BackgroundWorker, RunsJobsInOrderOneAtATimeOnAnotherThread) {
  std::vector<int> order;  // written by the worker only; read after finish()
  std::atomic<int> running{0}, most_at_once{0};
  std::atomic<bool> on_caller_thread{false};
  const std::thread::id caller = std::this_thread::get_id();
  {
    BackgroundWorker worker;
    for (int k = 0; k < 20; ++k)
      worker.submit([&, k] {
        const int now = ++running;
        if (now > most_at_once) most_at_once = now;
        if (std::this_thread::get_id() == caller) on_caller_thread = true;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        order.push_back(k);
        --running;
      });
    worker.finish();
    ASSERT_EQ(order.size(), 20u);
    for (int k = 0; k < 20; ++k) EXPECT_EQ(order[k], k);
  }
  EXPECT_EQ(most_at_once.load(), 1);
  EXPECT_FALSE(on_caller_thread.load());
}

TEST(BackgroundWorker, AFailureReachesTheCallerOnceAndTheWorkerGoesOn) {
  BackgroundWorker worker;
  worker.submit([] { throw std::runtime_error("disk full"); });
  try {
    worker.submit([] {});
    FAIL() << "the first job's failure was not rethrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "disk full");
  }
  // The job given to the failed submit() was not taken; the worker still runs new ones.
  bool ran = false;
  worker.submit([&] { ran = true; });
  worker.finish();
  EXPECT_TRUE(ran);
  worker.submit([] { throw std::runtime_error("late"); });
  EXPECT_THROW(worker.finish(), std::runtime_error);
  EXPECT_NO_THROW(worker.finish());  // reported once
}

// A latch the jobs wait on, opened by the test.
class Gate {
 public:
  void wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    opened_.wait(lock, [this] { return open_; });
  }
  void open() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      open_ = true;
    }
    opened_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable opened_;
  bool open_ = false;
};

TEST(BackgroundWorker, SubmitWaitsOnlyWhenTheJobsInTheWorkerWouldWeighMoreThanItsCapacity) {
  Gate gate;
  std::atomic<int> done{0};
  BackgroundWorker worker(3.0);
  for (int k = 0; k < 3; ++k)  // weight 3 in all: taken at once, though none can finish
    worker.submit([&] {
      gate.wait();
      ++done;
    });
  EXPECT_EQ(done.load(), 0);
  // A fourth would make 4: it waits until a job ends.
  std::future<void> fourth = std::async(std::launch::async, [&] { worker.submit([&] { ++done; }); });
  EXPECT_EQ(fourth.wait_for(std::chrono::milliseconds(100)), std::future_status::timeout);
  gate.open();
  fourth.get();
  // A job heavier than the capacity is taken when the worker is empty.
  worker.submit([&] { ++done; }, 10.0);
  worker.finish();
  EXPECT_EQ(done.load(), 5);
}

}  // namespace
}  // namespace facetool
