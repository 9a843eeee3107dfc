// The process pool of `omnidso ablate`: exit codes, signals, timeouts, logs, the job limit.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <omnidso/cli/process_pool.hpp>
#include <omnidso/core/error.hpp>

#include "synth_test_util.hpp"

namespace omnidso::cli {
namespace {

ProcessSpec shell(const std::string& script, const std::string& log, double timeout_s = 0) {
  return {{"/bin/sh", "-c", script}, log, timeout_s};
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ProcessPoolTest, ReportsExitStatusAndCapturesBothStreamsInTheLog) {
  test::TempDir tmp("pool_exit");
  const std::string ok_log = tmp.str() + "/ok.txt", bad_log = tmp.str() + "/bad.txt";
  const auto outcomes = runProcesses(
      {shell("echo to-stdout; echo to-stderr >&2", ok_log), shell("exit 3", bad_log)}, 2);
  ASSERT_EQ(outcomes.size(), 2u);
  EXPECT_TRUE(outcomes[0].succeeded());
  EXPECT_EQ(outcomes[1].kind, ProcessOutcome::Kind::kExited);
  EXPECT_EQ(outcomes[1].exit_code, 3);
  EXPECT_FALSE(outcomes[1].succeeded());
  EXPECT_EQ(outcomes[1].describe(), "exit status 3");
  EXPECT_EQ(readFile(ok_log), "to-stdout\nto-stderr\n");
}

TEST(ProcessPoolTest, KillsAProcessThatExceedsItsTimeout) {
  test::TempDir tmp("pool_timeout");
  const auto outcomes = runProcesses({shell("sleep 30", tmp.str() + "/log.txt", 0.2)}, 1);
  EXPECT_EQ(outcomes[0].kind, ProcessOutcome::Kind::kTimedOut);
  EXPECT_FALSE(outcomes[0].succeeded());
  EXPECT_NE(outcomes[0].describe().find("timeout"), std::string::npos);
}

TEST(ProcessPoolTest, ReportsACrashAsTheSignal) {
  test::TempDir tmp("pool_signal");
  const auto outcomes = runProcesses({shell("kill -SEGV $$", tmp.str() + "/log.txt")}, 1);
  EXPECT_EQ(outcomes[0].kind, ProcessOutcome::Kind::kSignaled);
  EXPECT_EQ(outcomes[0].signal, SIGSEGV);
}

TEST(ProcessPoolTest, AMissingExecutableIsNotStartedAndNamed) {
  test::TempDir tmp("pool_missing");
  const auto outcomes =
      runProcesses({{{tmp.str() + "/no-such-program"}, tmp.str() + "/log.txt", 0}}, 1);
  EXPECT_EQ(outcomes[0].kind, ProcessOutcome::Kind::kNotStarted);
  EXPECT_NE(outcomes[0].describe().find("no-such-program"), std::string::npos);
}

TEST(ProcessPoolTest, NeverRunsMoreThanJobsAtOnceAndFinishesEveryProcess) {
  test::TempDir tmp("pool_jobs");
  std::vector<ProcessSpec> specs;
  for (int i = 0; i < 5; ++i)
    specs.push_back(shell("sleep 0.1", tmp.str() + "/log" + std::to_string(i)));
  int running = 0, most = 0, finished = 0;
  ProcessCallbacks callbacks;
  callbacks.started = [&](size_t) { most = std::max(most, ++running); };
  callbacks.finished = [&](size_t, const ProcessOutcome& o) {
    --running;
    ++finished;
    EXPECT_TRUE(o.succeeded());
  };
  runProcesses(specs, 2, callbacks);
  EXPECT_EQ(most, 2);
  EXPECT_EQ(finished, 5);
  EXPECT_THROW(runProcesses(specs, 0), Error);
}

}  // namespace
}  // namespace omnidso::cli
