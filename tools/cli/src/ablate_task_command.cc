// `omnidso ablate-task`: one run of an ablation inside another scheduler's task (see
// ablation_task.hpp for the contract). Not meant to be typed by hand; the scripts and job
// lists of `omnidso ablate --executor slurm|parallel` call it.
#include <CLI/CLI.hpp>
#include <signal.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/cli/ablation_task.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/cli/process_pool.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

struct TaskArguments {
  std::string run_directory;
  std::vector<std::string> command;
  double timeout_s = 0;
};

// The terminating signals, blocked so that they are noticed between polls rather than
// killing this process before it can stop the run.
sigset_t terminatingSignals() {
  sigset_t set;
  sigemptyset(&set);
  for (int s : {SIGTERM, SIGINT, SIGHUP}) sigaddset(&set, s);
  return set;
}

int pendingTerminatingSignal() {
  sigset_t pending;
  sigpending(&pending);
  for (int s : {SIGTERM, SIGINT, SIGHUP})
    if (sigismember(&pending, s)) return s;
  return 0;
}

void runTask(const TaskArguments& args) {
  const fs::path dir(args.run_directory);
  if (fs::exists(dir / "result.json")) {
    std::cout << args.run_directory << ": finished earlier, left alone\n";
    return;
  }
  PlannedRun run = readPlannedRun(args.run_directory);
  if (args.command.empty()) throw Error("ablate-task: no command after --");
  fs::remove(dir / kClusterFailureFile);  // an earlier attempt's; this one decides anew
  const sigset_t terminating = terminatingSignals();
  sigprocmask(SIG_BLOCK, &terminating, nullptr);
  ProcessCallbacks callbacks;
  callbacks.interrupted = [] { return pendingTerminatingSignal() != 0; };
  const ProcessOutcome outcome =
      runProcesses({{args.command, (dir / "log.txt").string(), args.timeout_s}}, 1, callbacks)[0];
  // A scheduler that stops the task signals the run too: the run's death by that signal is the
  // scheduler's doing, not the run's failure. Give our own signal a moment to arrive.
  int stop_signal = pendingTerminatingSignal();
  if (!stop_signal && outcome.kind == ProcessOutcome::Kind::kSignaled) {
    const timespec grace{1, 0};
    stop_signal = std::max(0, sigtimedwait(&terminating, nullptr, &grace));
  }
  // Under Slurm a SIGKILL from outside is the cluster's (the OOM killer of the job's cgroup,
  // the end of KillWait): sacct knows why, and the run is not finished.
  if (!stop_signal && outcome.kind == ProcessOutcome::Kind::kSignaled &&
      outcome.signal == SIGKILL && std::getenv("SLURM_JOB_ID"))
    stop_signal = SIGKILL;
  if (stop_signal) {
    std::cerr << args.run_directory << ": stopped by signal " << stop_signal
              << ", no result written\n";
    std::exit(128 + stop_signal);
  }
  const RunResult result = classifyRun(run, outcome);
  writeRunResult(args.run_directory, result);
  std::cout << args.run_directory << ": " << (result.ok ? "ok" : "failed: " + result.failure)
            << "\n";
}

}  // namespace

void registerAblateTaskCommand(CLI::App& app) {
  auto args = std::make_shared<TaskArguments>();
  CLI::App* cmd = app.add_subcommand(
      "ablate-task",
      "one run of an ablation as a Slurm or GNU parallel task (written into their scripts by "
      "`omnidso ablate --executor slurm|parallel`): runs the command after --, writes "
      "RUN_DIR/result.json");
  cmd->add_option("run_dir", args->run_directory, "the run's directory (holds planned.json)")
      ->required();
  cmd->add_option("command", args->command, "-- then the `omnidso run` command line")->required();
  cmd->add_option("--timeout", args->timeout_s, "seconds before the run is killed (0: none)")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([args] { runTask(*args); });
}

}  // namespace omnidso::cli
