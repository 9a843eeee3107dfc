// Reading what squeue and sacct say about a job array. The inputs are their real output
// (Slurm 22.05 on a single node: a task cancelled with scancel, one past its --time, three
// completed, then a folded range of pending tasks as sacct prints it).
#include <gtest/gtest.h>

#include <omnidso/cli/slurm_accounting.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {
namespace {

constexpr const char* kSacct =
    "5_0|CANCELLED by 0|0:0|00:00:01|vm|None\n"
    "5_0.batch|CANCELLED|0:15|00:00:01|vm|\n"
    "5_1|TIMEOUT|0:0|00:01:20|vm|None\n"
    "5_1.batch|CANCELLED|0:15|00:01:20|vm|\n"
    "5_2|COMPLETED|0:0|00:00:04|vm|JobArrayTaskLimit\n"
    "15_2|OUT_OF_MEMORY|0:125|00:03:00|vm|OutOfMemory\n"
    "5_[3-4,7%2]|PENDING|0:0|00:00:00|None assigned|JobArrayTaskLimit\n";

TEST(SlurmAccountingTest, ReadsEveryTaskOfTheJobAndExpandsFoldedRanges) {
  const auto tasks = cli::parseSlurmTaskStates(kSacct, "5");
  ASSERT_EQ(tasks.size(), 6u);  // 0, 1, 2, 3, 4, 7; not the steps, not job 15
  EXPECT_EQ(tasks.at(0).state, "CANCELLED");
  EXPECT_EQ(tasks.at(0).state_text, "CANCELLED by 0");
  EXPECT_EQ(tasks.at(0).exit_code, "0:0") << "the allocation's line, not the batch step's";
  EXPECT_EQ(tasks.at(1).state, "TIMEOUT");
  EXPECT_EQ(tasks.at(1).elapsed, "00:01:20");
  EXPECT_EQ(tasks.at(2).state, "COMPLETED");
  for (int i : {3, 4, 7}) EXPECT_EQ(tasks.at(i).state, "PENDING") << i;
  EXPECT_EQ(tasks.count(5), 0u);
  EXPECT_EQ(cli::parseSlurmTaskStates(kSacct, "15").at(2).state, "OUT_OF_MEMORY");
  // squeue's two columns.
  const auto queued = cli::parseSlurmTaskStates("7_1|RUNNING\n7_[2-3]|PENDING\n", "7");
  EXPECT_EQ(queued.size(), 3u);
  EXPECT_EQ(queued.at(1).state, "RUNNING");
}

TEST(SlurmAccountingTest, RefusesLinesItCannotRead) {
  EXPECT_THROW(cli::parseSlurmTaskStates("5_x|RUNNING\n", "5"), Error);
  EXPECT_THROW(cli::parseSlurmTaskStates("5_[2-|PENDING\n", "5"), Error);
  EXPECT_THROW(cli::parseSlurmTaskStates("no separator\n", "5"), Error);
  EXPECT_TRUE(cli::parseSlurmTaskStates("\n  \n", "5").empty());
}

TEST(SlurmAccountingTest, ActiveStatesAreTheOnesThatHaveNotEnded) {
  for (const char* s : {"PENDING", "RUNNING", "CONFIGURING", "COMPLETING", "SUSPENDED"})
    EXPECT_TRUE(cli::isActiveSlurmState(s)) << s;
  for (const char* s : {"COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "PREEMPTED",
                        "OUT_OF_MEMORY", "BOOT_FAIL", "DEADLINE"})
    EXPECT_FALSE(cli::isActiveSlurmState(s)) << s;
}

TEST(SlurmAccountingTest, TheReasonNamesTheStateTheTaskAndWhatSacctAdds) {
  const auto tasks = cli::parseSlurmTaskStates(kSacct, "5");
  EXPECT_EQ(cli::slurmFailureReason("5", 0, tasks.at(0), "/o/task-0.out"),
            "Slurm: CANCELLED by 0 (job 5_0 on vm after 00:00:01, exit code 0:0)");
  EXPECT_EQ(cli::slurmFailureReason("5", 1, tasks.at(1), "/o/task-1.out"),
            "Slurm: TIMEOUT (job 5_1 on vm after 00:01:20, exit code 0:0)");
  EXPECT_EQ(cli::slurmFailureReason("15", 2, cli::parseSlurmTaskStates(kSacct, "15").at(2), "t"),
            "Slurm: OUT_OF_MEMORY (job 15_2 on vm after 00:03:00, exit code 0:125, reason "
            "OutOfMemory)");
  // A task that ended by itself without a result.json points at its output.
  cli::SlurmTaskState failed{"FAILED", "FAILED", "127:0", "00:00:00", "n3", "NonZeroExitCode"};
  EXPECT_NE(cli::slurmFailureReason("9", 4, failed, "/o/task-4.out").find("see /o/task-4.out"),
            std::string::npos);
}

}  // namespace
}  // namespace omnidso
