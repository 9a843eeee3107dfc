// `omnidso ablate-task`, the wrapper of one run inside a Slurm or GNU parallel task: it writes
// the run's result.json as the local executor would, leaves a finished run alone, and when
// the scheduler stops it (SIGTERM) it stops the run and writes nothing.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <omnidso/cli/ablation_task.hpp>
#include <thread>

#include "ablate_test_util.hpp"
#include "core/temp_dir.hpp"

extern char** environ;

namespace omnidso {
namespace {
namespace fs = std::filesystem;

cli::PlannedRun plannedRun(const std::string& dir) {
  cli::PlannedRun run;
  run.run = 2;
  run.seed = 7;
  run.directory = dir;
  run.settings = {{"seed", 7}, {"camera_model", "native"}};
  cli::writePlannedRun(run);
  return run;
}

// `omnidso ablate-task RUN_DIR -- sh -c SCRIPT`; returns the child's pid.
pid_t startTask(const std::string& run_dir, const std::string& script) {
  std::vector<std::string> argv = {OMNIDSO_EXECUTABLE, "ablate-task", "--timeout", "60",
                                   run_dir,            "--",          "/bin/sh",   "-c",
                                   script};
  std::vector<char*> args;
  for (std::string& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  pid_t pid = -1;
  EXPECT_EQ(::posix_spawn(&pid, args[0], nullptr, nullptr, args.data(), environ), 0);
  return pid;
}

int exitStatus(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(AblateTaskCommandTest, WritesTheResultOnceAndLeavesAFinishedRunAlone) {
  test::TempDir dir;
  const std::string run_dir = dir.file("run2");
  plannedRun(run_dir);
  // A run that exits 3: failed, with the status and its last log line, seed and settings kept.
  EXPECT_EQ(exitStatus(startTask(run_dir, "echo bad input >&2; exit 3")), 0);
  const auto result = nlohmann::json::parse(test::readFile(run_dir + "/result.json"));
  EXPECT_EQ(result["status"], "failed");
  EXPECT_EQ(result["failure"], "exit status 3: bad input");
  EXPECT_EQ(result["seed"], 7);
  EXPECT_EQ(result["run"], 2);
  EXPECT_EQ(result["settings"]["camera_model"], "native");
  const auto written = fs::last_write_time(run_dir + "/result.json");
  EXPECT_EQ(exitStatus(startTask(run_dir, "touch " + dir.file("ran"))), 0);
  EXPECT_FALSE(fs::exists(dir.file("ran"))) << "a finished run is not run again";
  EXPECT_EQ(fs::last_write_time(run_dir + "/result.json"), written);
  // No planned.json: not a run of an ablation, exit status 2.
  fs::create_directories(dir.file("other"));
  EXPECT_EQ(exitStatus(startTask(dir.file("other"), "true")), 2);
}

TEST(AblateTaskCommandTest, StoppedBySigtermItStopsTheRunAndWritesNoResult) {
  test::TempDir dir;
  const std::string run_dir = dir.file("run2");
  plannedRun(run_dir);
  const std::string pid_file = dir.file("run.pid");
  const pid_t task = startTask(run_dir, "echo $$ > " + pid_file + "; exec sleep 60");
  for (int i = 0; i < 200 && test::readFile(pid_file).empty(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const pid_t run = std::stoi(test::readFile(pid_file));
  ::kill(task, SIGTERM);
  EXPECT_EQ(exitStatus(task), 128 + SIGTERM);
  EXPECT_FALSE(fs::exists(run_dir + "/result.json"));
  EXPECT_NE(::kill(run, 0), 0) << "the run was stopped with its task";
}

}  // namespace
}  // namespace omnidso
