#include <omnidso/frontend/mapping_worker.hpp>

namespace omnidso {

MappingWorker::MappingWorker() : thread_([this] { run(); }) {}

MappingWorker::~MappingWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  work_available_.notify_all();
  thread_.join();
}

void MappingWorker::push(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  work_available_.notify_one();
}

size_t MappingWorker::pending() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return jobs_.size() + (running_job_ ? 1 : 0);
}

void MappingWorker::drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return jobs_.empty() && !running_job_; });
  if (error_) {
    const std::exception_ptr error = error_;
    error_ = nullptr;
    std::rethrow_exception(error);
  }
}

void MappingWorker::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_available_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
    if (jobs_.empty()) return;  // stopping, nothing left
    std::function<void()> job = std::move(jobs_.front());
    jobs_.pop_front();
    running_job_ = true;
    const bool skip = error_ != nullptr;  // after a failure the rest waits for drain()
    lock.unlock();
    try {
      if (!skip) job();
    } catch (...) {
      lock.lock();
      if (!error_) error_ = std::current_exception();
      lock.unlock();
    }
    lock.lock();
    running_job_ = false;
    if (jobs_.empty()) idle_.notify_all();
  }
}

}  // namespace omnidso
