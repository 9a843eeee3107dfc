#include <fcntl.h>
#include <fmt/core.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <omnidso/cli/process_pool.hpp>
#include <omnidso/core/error.hpp>
#include <thread>

extern char** environ;

namespace omnidso::cli {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct RunningProcess {
  std::size_t index;
  pid_t pid;
  Clock::time_point start;
};

// posix_spawn with the log file as stdout and stderr; returns the pid or an error text.
pid_t spawn(const ProcessSpec& spec, std::string& error) {
  if (spec.argv.empty()) {
    error = "empty command line";
    return -1;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, spec.log_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // A caller that blocks SIGTERM (omnidso ablate-task) must not pass that on to the run.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t none, terminating;
  sigemptyset(&none);
  sigemptyset(&terminating);
  for (int s : {SIGTERM, SIGINT, SIGHUP}) sigaddset(&terminating, s);
  posix_spawnattr_setsigmask(&attributes, &none);
  posix_spawnattr_setsigdefault(&attributes, &terminating);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  std::vector<char*> argv;
  for (const std::string& a : spec.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    error =
        fmt::format("cannot start {} (log {}): {}", spec.argv[0], spec.log_path, std::strerror(rc));
    return -1;
  }
  return pid;
}

ProcessOutcome outcomeOf(int status) {
  ProcessOutcome outcome;
  if (WIFEXITED(status)) {
    outcome.kind = ProcessOutcome::Kind::kExited;
    outcome.exit_code = WEXITSTATUS(status);
  } else {
    outcome.kind = ProcessOutcome::Kind::kSignaled;
    outcome.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  }
  return outcome;
}

// waitpid, retried on EINTR; returns 0 while the child runs (non-blocking).
pid_t waitFor(pid_t pid, int& status, bool block) {
  pid_t r;
  do {
    r = ::waitpid(pid, &status, block ? 0 : WNOHANG);
  } while (r < 0 && errno == EINTR);
  if (r < 0) throw Error(fmt::format("waitpid({}): {}", pid, std::strerror(errno)));
  return r;
}

}  // namespace

std::string ProcessOutcome::describe() const {
  switch (kind) {
    case Kind::kExited:
      return fmt::format("exit status {}", exit_code);
    case Kind::kSignaled:
      return fmt::format("killed by signal {} ({})", signal, strsignal(signal));
    case Kind::kTimedOut:
    case Kind::kNotStarted:
      return error;
  }
  return error;
}

std::vector<ProcessOutcome> runProcesses(const std::vector<ProcessSpec>& specs, int jobs,
                                         const ProcessCallbacks& callbacks) {
  if (jobs < 1) throw Error(fmt::format("jobs must be at least 1, got {}", jobs));
  std::vector<ProcessOutcome> outcomes(specs.size());
  std::vector<RunningProcess> running;
  std::size_t next = 0;
  auto finish = [&](std::size_t index, ProcessOutcome outcome) {
    outcomes[index] = std::move(outcome);
    if (callbacks.finished) callbacks.finished(index, outcomes[index]);
  };
  while (next < specs.size() || !running.empty()) {
    if (callbacks.interrupted && callbacks.interrupted()) {
      for (const RunningProcess& p : running) {
        int status = 0;
        ::kill(p.pid, SIGKILL);
        waitFor(p.pid, status, true);
        ProcessOutcome outcome = outcomeOf(status);
        outcome.wall_s = secondsSince(p.start);
        finish(p.index, outcome);
      }
      break;
    }
    while (next < specs.size() && static_cast<int>(running.size()) < jobs) {
      const std::size_t index = next++;
      std::string error;
      const Clock::time_point start = Clock::now();
      const pid_t pid = spawn(specs[index], error);
      if (callbacks.started) callbacks.started(index);
      if (pid < 0) {
        ProcessOutcome failed;
        failed.error = error;
        finish(index, failed);
      } else {
        running.push_back({index, pid, start});
      }
    }
    bool reaped = false;
    for (auto it = running.begin(); it != running.end();) {
      const ProcessSpec& spec = specs[it->index];
      int status = 0;
      ProcessOutcome outcome;
      if (waitFor(it->pid, status, false) == it->pid) {
        outcome = outcomeOf(status);
      } else if (spec.timeout_s > 0 && secondsSince(it->start) > spec.timeout_s) {
        ::kill(it->pid, SIGKILL);
        waitFor(it->pid, status, true);
        outcome.kind = ProcessOutcome::Kind::kTimedOut;
        outcome.error = fmt::format("timeout after {:g} s", spec.timeout_s);
      } else {
        ++it;
        continue;
      }
      outcome.wall_s = secondsSince(it->start);
      const std::size_t index = it->index;
      it = running.erase(it);
      finish(index, outcome);
      reaped = true;
    }
    if (!reaped && !running.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return outcomes;
}

}  // namespace omnidso::cli
