// TaskPool (task_pool.hpp): workers sleep on a condition variable until a run publishes a new
// generation, then take task indices from one atomic counter until none is left.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <omnidso/core/task_pool.hpp>
#include <thread>
#include <vector>

namespace omnidso {
namespace {
thread_local const TaskPool* running_pool = nullptr;  // the pool whose task this thread runs
}  // namespace

struct TaskPool::Impl {
  std::vector<std::thread> workers;
  std::mutex run_mutex;  // held by the thread whose run uses the workers

  std::mutex mutex;  // guards everything below
  std::condition_variable wake, finished;
  const std::function<void(int)>* task = nullptr;
  int num_tasks = 0;
  unsigned long generation = 0;
  int busy_workers = 0;
  bool stop = false;
  int error_index = -1;
  std::exception_ptr error;
  std::atomic<int> next{0};

  // Takes task indices until none is left; keeps the exception of the lowest index.
  void drain(const TaskPool* pool) {
    const TaskPool* outer = running_pool;
    running_pool = pool;
    for (int i = next.fetch_add(1); i < num_tasks; i = next.fetch_add(1)) {
      try {
        (*task)(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (error_index < 0 || i < error_index) {
          error_index = i;
          error = std::current_exception();
        }
      }
    }
    running_pool = outer;
  }

  void workerLoop(const TaskPool* pool) {
    unsigned long seen = 0;
    while (true) {
      {
        std::unique_lock<std::mutex> lock(mutex);
        wake.wait(lock, [&] { return stop || generation != seen; });
        if (stop) return;
        seen = generation;
      }
      drain(pool);
      std::lock_guard<std::mutex> lock(mutex);
      if (--busy_workers == 0) finished.notify_one();
    }
  }
};

TaskPool::TaskPool(int num_threads) : impl_(std::make_unique<Impl>()) {
  for (int i = 1; i < num_threads; ++i)
    impl_->workers.emplace_back([this] { impl_->workerLoop(this); });
}

TaskPool::~TaskPool() {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stop = true;
  }
  impl_->wake.notify_all();
  for (std::thread& t : impl_->workers) t.join();
}

int TaskPool::numThreads() const { return static_cast<int>(impl_->workers.size()) + 1; }

void TaskPool::run(int num_tasks, const std::function<void(int)>& task) {
  if (num_tasks <= 0) return;
  std::unique_lock<std::mutex> run_lock(impl_->run_mutex, std::defer_lock);
  if (impl_->workers.empty() || num_tasks == 1 || running_pool == this || !run_lock.try_lock()) {
    for (int i = 0; i < num_tasks; ++i) task(i);
    return;
  }
  Impl& s = *impl_;
  {
    std::lock_guard<std::mutex> lock(s.mutex);
    s.task = &task;
    s.num_tasks = num_tasks;
    s.next.store(0);
    s.error_index = -1;
    s.error = nullptr;
    s.busy_workers = static_cast<int>(s.workers.size());
    ++s.generation;
  }
  s.wake.notify_all();
  s.drain(this);
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(s.mutex);
    s.finished.wait(lock, [&] { return s.busy_workers == 0; });
    s.task = nullptr;
    error = s.error;
    s.error = nullptr;
  }
  if (error) std::rethrow_exception(error);
}

int defaultComputeThreads() {
  // At most 8: the window's evaluation has one task per host–target pair (≈ 40 with 7
  // keyframes) and activation refines batches of 64, so more threads would mostly wake up to
  // find nothing left.
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(std::min(n, 8u));
}

}  // namespace omnidso
