#pragma once
// A stopwatch on std::chrono::steady_clock (monotonic, unaffected by clock changes), for
// the per-stage timings the odometry reports. Milliseconds as double.

#include <chrono>

namespace omnidso {

class Stopwatch {
 public:
  using Clock = std::chrono::steady_clock;

  Stopwatch() : start_(Clock::now()) {}

  void restart() { start_ = Clock::now(); }

  double elapsedMs() const {
    return std::chrono::duration<double, std::milli>(Clock::now() - start_).count();
  }

  // The elapsed time, then restarts: convenient for timing consecutive stages.
  double lapMs() {
    const Clock::time_point now = Clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - start_).count();
    start_ = now;
    return ms;
  }

 private:
  Clock::time_point start_;
};

}  // namespace omnidso
