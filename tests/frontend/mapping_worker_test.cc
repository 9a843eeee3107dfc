// The real-time mode's mapping thread: jobs run in order, drain() waits for all of them, and
// an exception in a job reaches the caller at the next drain().
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <omnidso/frontend/mapping_worker.hpp>
#include <stdexcept>
#include <thread>
#include <vector>

namespace omnidso {
namespace {

TEST(MappingWorker, RunsJobsInOrderAndDrainWaitsForAll) {
  MappingWorker worker;
  std::vector<int> order;  // touched by the worker only, read after drain()
  for (int i = 0; i < 50; ++i)
    worker.push([&order, i] {
      if (i % 10 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
      order.push_back(i);
    });
  worker.drain();
  ASSERT_EQ(order.size(), 50u);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(order[i], i);
  EXPECT_EQ(worker.pending(), 0u);
}

TEST(MappingWorker, ExceptionOfAJobIsRethrownByDrainAndLaterJobsWait) {
  MappingWorker worker;
  std::atomic<int> ran{0};
  worker.push([] { throw std::runtime_error("window failed"); });
  worker.push([&ran] { ++ran; });  // skipped: the failure must be seen first
  EXPECT_THROW(worker.drain(), std::runtime_error);
  EXPECT_EQ(ran.load(), 0);
  worker.push([&ran] { ++ran; });  // after the report, work goes on
  worker.drain();
  EXPECT_EQ(ran.load(), 1);
}

TEST(MappingWorker, DestructorFinishesQueuedJobs) {
  std::atomic<int> ran{0};
  {
    MappingWorker worker;
    for (int i = 0; i < 20; ++i) worker.push([&ran] { ++ran; });
  }
  EXPECT_EQ(ran.load(), 20);
}

}  // namespace
}  // namespace omnidso
