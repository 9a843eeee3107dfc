#include "omnidso/core/task_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace omnidso {
namespace {

class TaskPoolTest : public ::testing::TestWithParam<int> {};

TEST_P(TaskPoolTest, RunsEveryTaskExactlyOnce) {
  TaskPool pool(GetParam());
  EXPECT_EQ(pool.numThreads(), std::max(GetParam(), 1));
  for (int n : {0, 1, 2, 3, 17, 1000}) {
    std::vector<std::atomic<int>> calls(n);
    pool.run(n, [&](int i) { calls[i].fetch_add(1); });
    for (int i = 0; i < n; ++i) ASSERT_EQ(calls[i].load(), 1) << "task " << i << " of " << n;
  }
}

TEST_P(TaskPoolTest, ManyRunsInARowAllComplete) {
  // Generations follow each other quickly: a worker must never miss one or run one twice.
  TaskPool pool(GetParam());
  std::vector<long> sums(64, 0);
  for (int round = 0; round < 2000; ++round)
    pool.run(64, [&](int i) { sums[i] += i; });
  for (int i = 0; i < 64; ++i) EXPECT_EQ(sums[i], 2000L * i);
}

TEST_P(TaskPoolTest, RethrowsTheLowestFailingTaskAfterAllFinished) {
  TaskPool pool(GetParam());
  std::atomic<int> done{0};
  try {
    pool.run(100, [&](int i) {
      done.fetch_add(1);
      if (i == 40 || i == 70) throw std::runtime_error("task " + std::to_string(i));
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "task 40");
  }
  // The sequential path stops at the first throw; the workers finish or skip the rest.
  EXPECT_GE(done.load(), 41);
  // The pool is usable after a failure.
  std::atomic<int> after{0};
  pool.run(10, [&](int) { after.fetch_add(1); });
  EXPECT_EQ(after.load(), 10);
}

TEST_P(TaskPoolTest, NestedRunsRunInlineWithoutDeadlock) {
  TaskPool pool(GetParam());
  std::vector<std::atomic<int>> calls(8 * 8);
  pool.run(8, [&](int i) { pool.run(8, [&](int j) { calls[8 * i + j].fetch_add(1); }); });
  for (auto& c : calls) EXPECT_EQ(c.load(), 1);
}

TEST_P(TaskPoolTest, TwoCallersShareThePool) {
  // The real-time mode's tracking and mapping threads may both reach the pool: the second
  // caller runs its tasks itself instead of waiting.
  TaskPool pool(GetParam());
  std::vector<std::atomic<int>> a(500), b(500);
  std::thread other([&] {
    for (int r = 0; r < 50; ++r) pool.run(10, [&](int i) { b[50 * (r % 10) + i].fetch_add(1); });
  });
  for (int r = 0; r < 50; ++r) pool.run(10, [&](int i) { a[50 * (r % 10) + i].fetch_add(1); });
  other.join();
  for (int k = 0; k < 10; ++k)
    for (int i = 0; i < 10; ++i) {
      EXPECT_EQ(a[50 * k + i].load(), 5);
      EXPECT_EQ(b[50 * k + i].load(), 5);
    }
}

TEST(TaskPool, RunTasksWithoutAPoolRunsInOrder) {
  std::vector<int> order;
  runTasks(nullptr, 5, [&](int i) { order.push_back(i); });
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_GE(defaultComputeThreads(), 1);
}

INSTANTIATE_TEST_SUITE_P(Threads, TaskPoolTest, ::testing::Values(1, 2, 4),
                         [](const auto& info) { return "T" + std::to_string(info.param); });

}  // namespace
}  // namespace omnidso
