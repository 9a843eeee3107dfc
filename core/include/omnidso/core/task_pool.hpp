#pragma once
// A fixed set of worker threads that run indexed tasks: run(n, task) calls task(i) once for
// every i in [0, n), on the calling thread and the workers, and returns when all are done.
//
// Why: the deterministic mode must give the same trajectory bit for bit, yet a 2-core machine
// should not leave a core idle while a keyframe is mapped. The pool therefore promises
// nothing about which thread runs which task or in what order; its callers split work so
// that every task writes only its own outputs and every floating-point sum is formed by one
// task in a fixed order (per epipolar trace, per host–target pair of the window). The result
// is then the same whatever the number of threads, including one — which the window solver's
// and the odometry's thread-count tests check; `task_pool_test.cc` checks the pool.
//
// A run that cannot use the workers — the pool has none, one task, a task of this pool asks
// for another run, or another thread is already running — runs its tasks in order on the
// calling thread, so nesting and sharing never deadlock. An exception thrown by a task is
// rethrown by run() after every task has finished or been skipped: the one of the lowest
// task index, as the sequential order would have thrown it.

#include <functional>
#include <memory>

namespace omnidso {

class TaskPool {
 public:
  // `num_threads` counts the calling thread: 1 (or less) runs everything on the caller.
  explicit TaskPool(int num_threads);
  ~TaskPool();
  TaskPool(const TaskPool&) = delete;
  TaskPool& operator=(const TaskPool&) = delete;

  int numThreads() const;
  void run(int num_tasks, const std::function<void(int)>& task);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// run(n, task) on `pool`, or in order on the calling thread when `pool` is null.
inline void runTasks(TaskPool* pool, int num_tasks, const std::function<void(int)>& task) {
  if (pool) {
    pool->run(num_tasks, task);
    return;
  }
  for (int i = 0; i < num_tasks; ++i) task(i);
}

// The thread count `0` stands for: the machine's hardware threads, at least 1 and at most 8.
int defaultComputeThreads();

}  // namespace omnidso
