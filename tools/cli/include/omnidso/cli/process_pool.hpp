#pragma once
// Child processes run J at a time: each with its stdout and stderr in a log file, stdin from
// /dev/null, the default signal mask and dispositions (whatever the caller blocks), and an
// optional wall-clock limit after which it is killed (SIGKILL). Used by
// `omnidso ablate` to run every `omnidso run` as a separate process.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace omnidso::cli {

struct ProcessSpec {
  std::vector<std::string> argv;  // argv[0]: path of the executable (no PATH search)
  std::string log_path;           // created or truncated; its directory must exist
  double timeout_s = 0;           // 0: no limit
};

struct ProcessOutcome {
  enum class Kind {
    kExited,      // exit_code holds the status
    kSignaled,    // killed by `signal` (a crash, or killed from outside)
    kTimedOut,    // killed by us after timeout_s
    kNotStarted,  // posix_spawn failed; `error` says why
  };
  Kind kind = Kind::kNotStarted;
  int exit_code = 0;
  int signal = 0;
  double wall_s = 0;
  std::string error;

  bool succeeded() const { return kind == Kind::kExited && exit_code == 0; }
  // "exit status 3", "killed by signal 11 (Segmentation fault)", "timeout after 60 s", ...
  std::string describe() const;
};

struct ProcessCallbacks {
  std::function<void(std::size_t index)> started;
  std::function<void(std::size_t index, const ProcessOutcome& outcome)> finished;
  // Polled while processes run; once it returns true, the running processes are killed
  // (SIGKILL; `finished` reports them killed) and the rest are not started (no callback).
  std::function<bool()> interrupted;
};

// Starts specs in list order, keeping at most `jobs` (≥ 1) running, and waits for all of
// them. The callbacks run on the calling thread. Returns one outcome per spec.
std::vector<ProcessOutcome> runProcesses(const std::vector<ProcessSpec>& specs, int jobs,
                                         const ProcessCallbacks& callbacks = {});

}  // namespace omnidso::cli
