#pragma once
// One background thread that runs jobs in the order they were pushed: the odometry's
// real-time mode puts its mapping (epipolar search, keyframes, window, marginalisation) here
// so that tracking goes on in the caller's thread, as DSO's mapping thread does. Jobs run
// one at a time, so they need no locking among themselves; what they share with the caller
// is the caller's business. An exception thrown by a job is kept and rethrown by the next
// drain() (never lost, never thrown in the worker).

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace omnidso {

class MappingWorker {
 public:
  MappingWorker();
  ~MappingWorker();  // finishes the queued jobs, then joins
  MappingWorker(const MappingWorker&) = delete;
  MappingWorker& operator=(const MappingWorker&) = delete;

  void push(std::function<void()> job);
  // Jobs queued or running.
  size_t pending() const;
  // Waits until every job pushed so far has run; rethrows the first exception of a job.
  void drain();

 private:
  void run();

  mutable std::mutex mutex_;
  std::condition_variable work_available_, idle_;
  std::deque<std::function<void()>> jobs_;
  bool running_job_ = false;
  bool stopping_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace omnidso
