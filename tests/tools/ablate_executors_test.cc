// `omnidso ablate --executor slurm|parallel|--collect` in-process, with shell scripts on PATH
// standing in for sbatch, squeue, sacct and GNU parallel: the stand-in sbatch runs every array
// task of the submitted script at once (with bash, as slurmd would) except the ones listed in
// `cancel`, which it reports CANCELLED to squeue and sacct. The tasks run the real
// `omnidso ablate-task` around the stand-in `omnidso run` of ablate_test_util.hpp.
#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <omnidso/cli/commands.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/synth/dataset_writer.hpp>

#include "ablate_test_util.hpp"
#include "synth_test_util.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;

constexpr const char* kSbatch = R"(#!/bin/sh
here=$(dirname "$0"); script="$2"
echo "$@" >> "$here/sbatch_calls.txt"
job=$(cat "$here/next_job" 2>/dev/null || echo 100); echo $((job + 1)) > "$here/next_job"
tasks=$(grep -c '^  [0-9]*) exec' "$script"); : > "$here/states_$job"; i=0
while [ $i -lt $tasks ]; do
  if grep -qx "$i" "$here/cancel" 2>/dev/null; then
    echo "${job}_$i|CANCELLED by 0|0:0|00:00:02|node1|None" >> "$here/states_$job"
  else
    SLURM_ARRAY_TASK_ID=$i bash "$script" > /dev/null 2>&1
    echo "${job}_$i|COMPLETED|0:0|00:00:01|node1|None" >> "$here/states_$job"
  fi
  i=$((i + 1))
done
echo "$job"
)";
// squeue -h -r -t all -j JOB -o FORMAT / sacct -n -X -P -j JOB -o FIELDS: the job's states.
constexpr const char* kSqueue = R"(#!/bin/sh
here=$(dirname "$0"); echo "$@" >> "$here/squeue_calls.txt"
while [ "$1" != -j ]; do shift; done; cut -d'|' -f1,2 "$here/states_$2"
)";
constexpr const char* kSacct = R"(#!/bin/sh
here=$(dirname "$0"); while [ "$1" != -j ]; do shift; done; cat "$here/states_$2"
)";
// parallel --jobs J --joblog LOG [ARGS] :::: JOBS: runs each line, but line 2 "is killed".
constexpr const char* kParallel = R"(#!/bin/sh
here=$(dirname "$0"); echo "$@" > "$here/parallel_args.txt"
while [ "$1" != --joblog ]; do shift; done; log="$2"
while [ "$1" != :::: ]; do shift; done; jobs="$2"
printf 'Seq\tHost\tStarttime\tJobRuntime\tSend\tReceive\tExitval\tSignal\tCommand\n' > "$log"
n=0
while IFS= read -r line; do
  n=$((n + 1))
  if [ $n -eq 2 ]; then printf '2\tws2\t0\t7.5\t0\t0\t0\t15\tx\n' >> "$log"; continue; fi
  sh -c "$line" > /dev/null 2>&1 < /dev/null; printf '%s\t:\t0\t1\t0\t0\t%s\t0\tx\n' $n $? >> "$log"
done < "$jobs"
)";

void writeScript(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  ::chmod(path.c_str(), 0755);
}

void runAblate(const std::string& arguments) {
  CLI::App app;
  app.require_subcommand(1);
  cli::registerAblateCommand(app);
  app.parse("ablate --quiet " + arguments);
}

std::map<std::string, fs::file_time_type> finishedRunFiles(const std::string& out) {
  std::map<std::string, fs::file_time_type> files;
  for (const auto& e : fs::recursive_directory_iterator(out + "/runs"))
    if (e.is_regular_file() && fs::exists(e.path().parent_path() / "result.json"))
      files[e.path().string()] = e.last_write_time();
  return files;
}

class AblateExecutorsTest : public ::testing::Test {
 protected:
  AblateExecutorsTest() : tmp_("ablate_executors"), bin_(tmp_.str() + "/bin") {
    synth::SyntheticSequence sequence(test::smallSequenceConfig(6));
    synth::writeSyntheticDataset(sequence, tmp_.str() + "/seq");
    fs::create_directories(bin_);
    // `omnidso`: the real one for ablate-task, the stand-in for run.
    const std::string fake = test::kFakeRun;
    writeScript(bin_ + "/omnidso", "#!/bin/sh\nif [ \"$1\" = ablate-task ]; then exec '" +
                                       std::string(OMNIDSO_EXECUTABLE) + "' \"$@\"; fi\n" +
                                       fake.substr(fake.find('\n') + 1));
    writeScript(bin_ + "/sbatch", kSbatch);
    writeScript(bin_ + "/squeue", kSqueue);
    writeScript(bin_ + "/sacct", kSacct);
    writeScript(bin_ + "/parallel", kParallel);
    path_ = std::getenv("PATH");
    ::setenv("PATH", (bin_ + ":" + path_).c_str(), 1);
  }
  ~AblateExecutorsTest() override { ::setenv("PATH", path_.c_str(), 1); }

  // Cells native Kf5, native Kf3, pinhole-crop:90 Kf5, pinhole-crop:90 Kf3 (which fails).
  std::string arguments(const std::string& executor, int runs = 1) const {
    return "--datasets " + tmp_.str() +
           "/seq --camera-models native,pinhole-crop:90 --keyframes 5,3 --runs " +
           std::to_string(runs) + " --omnidso " + bin_ + "/omnidso --out " + out_ +
           " --executor " + executor;
  }
  test::TempDir tmp_;
  std::string bin_, path_, out_ = tmp_.str() + "/ablation";
};

TEST_F(AblateExecutorsTest, SlurmReportsACancelledTaskAndTheResubmissionRunsOnlyIt) {
  std::ofstream(bin_ + "/cancel") << "0\n";  // native Kf5
  runAblate(arguments("slurm") + " --jobs 3 --poll-interval 0.1 --slurm-time 0:10:00");
  const std::string script = test::readFile(out_ + "/slurm/submission-1/job.sh");
  EXPECT_NE(script.find("#SBATCH --array=0-3%3\n"), std::string::npos) << script;
  EXPECT_NE(script.find("#SBATCH --time=0:10:00\n"), std::string::npos) << script;
  EXPECT_EQ(test::readFile(bin_ + "/sbatch_calls.txt"),
            "--parsable " + out_ + "/slurm/submission-1/job.sh\n");
  EXPECT_EQ(test::readFile(out_ + "/slurm/submission-1/job_id"), "100\n");
  EXPECT_EQ(test::lineCount(bin_ + "/calls.txt"), 3u) << "3 runs performed";
  const std::string runs = test::readFile(out_ + "/runs.csv");
  EXPECT_NE(runs.find("seq,native,5,1,0,failed,\"Slurm: CANCELLED by 0 (job 100_0 on node1 after "
                      "00:00:02, exit code 0:0)\""),
            std::string::npos)
      << runs;
  EXPECT_NE(runs.find("seq,native,3,1,0,ok,"), std::string::npos) << runs;
  EXPECT_NE(runs.find("seq,pinhole-crop:90,3,1,0,failed,exit status 3: omnidso: error: fake"),
            std::string::npos)
      << runs;
  EXPECT_NE(test::readFile(out_ + "/tables.md").find("CANCELLED by 0"), std::string::npos);

  // Resubmitted: one task, the cancelled run; no finished run's file touched.
  fs::remove(bin_ + "/cancel");
  const auto before = finishedRunFiles(out_);
  runAblate(arguments("slurm") + " --poll-interval 0.1");
  const std::string again = test::readFile(out_ + "/slurm/submission-2/job.sh");
  EXPECT_NE(again.find("#SBATCH --array=0-0\n"), std::string::npos) << again;
  EXPECT_NE(again.find("seq__native__kf5/run1 -- "), std::string::npos) << again;
  EXPECT_EQ(test::lineCount(bin_ + "/calls.txt"), 4u);
  for (const auto& [file, time] : before) EXPECT_EQ(fs::last_write_time(file), time) << file;
  EXPECT_NE(test::readFile(out_ + "/runs.csv").find("seq,native,5,1,0,ok,"), std::string::npos);
  EXPECT_FALSE(fs::exists(out_ + "/runs/seq__native__kf5/run1/cluster.json"));
}

TEST_F(AblateExecutorsTest, CollectMarksWhatHasNotFinishedAndDryRunSubmitsNothing) {
  runAblate(arguments("slurm", 2) + " --dry-run");
  EXPECT_FALSE(fs::exists(bin_ + "/sbatch_calls.txt"));
  EXPECT_FALSE(fs::exists(out_ + "/tables.md")) << "nothing has run";
  const std::string script = out_ + "/slurm/submission-1/job.sh";
  for (int task : {0, 6})  // native Kf5 run 1; pinhole-crop:90 Kf3 run 1 (fails)
    ASSERT_EQ(std::system(("SLURM_ARRAY_TASK_ID=" + std::to_string(task) + " bash " + script +
                           " > /dev/null")
                              .c_str()),
              0);
  runAblate("--collect --out " + out_);
  const std::string runs = test::readFile(out_ + "/runs.csv");
  EXPECT_NE(runs.find("seq,native,5,1,0,ok,"), std::string::npos) << runs;
  EXPECT_NE(runs.find("seq,pinhole-crop:90,3,1,0,failed,exit status 3"), std::string::npos);
  EXPECT_NE(runs.find("seq,native,5,2,1,missing,not finished"), std::string::npos) << runs;
  const std::string md = test::readFile(out_ + "/tables.md");
  EXPECT_NE(md.find("0.0100 (missing 1/2)"), std::string::npos) << md;
  EXPECT_NE(md.find("failed 1/2, missing 1/2"), std::string::npos) << md;
  EXPECT_NE(md.find("6 runs have not finished"), std::string::npos) << md;
  EXPECT_NE(md.find("runs/seq__native__kf5/run2"), std::string::npos) << "listed as missing";
  EXPECT_THROW(runAblate("--collect --out " + tmp_.str() + "/nothing"), Error);
}

TEST_F(AblateExecutorsTest, ParallelPassesItsArgumentsAndRecordsAKilledJob) {
  runAblate(arguments("parallel") + " --jobs 2 --parallel-args \"--sshloginfile 'my hosts'\"");
  const std::string dir = out_ + "/parallel/submission-1";
  EXPECT_EQ(test::readFile(bin_ + "/parallel_args.txt"),
            "--jobs 2 --joblog " + dir + "/joblog.tsv --sshloginfile my hosts :::: " + dir +
                "/jobs.txt\n");
  EXPECT_EQ(test::lineCount(dir + "/jobs.txt"), 4u);
  EXPECT_EQ(test::lineCount(bin_ + "/calls.txt"), 3u);
  const std::string runs = test::readFile(out_ + "/runs.csv");
  EXPECT_NE(runs.find("seq,native,3,1,0,failed,\"GNU parallel: exit value 0, signal 15 (host ws2"),
            std::string::npos)
      << runs;
  runAblate(arguments("parallel"));  // only the killed job again
  EXPECT_EQ(test::lineCount(out_ + "/parallel/submission-2/jobs.txt"), 1u);
  EXPECT_EQ(test::lineCount(bin_ + "/calls.txt"), 4u);
}

TEST_F(AblateExecutorsTest, RefusesOptionsOfAnotherExecutor) {
  EXPECT_THROW(runAblate(arguments("local") + " --no-wait"), Error);
  EXPECT_THROW(runAblate(arguments("local") + " --dry-run"), Error);
  EXPECT_THROW(runAblate("--collect --datasets x --out " + out_), Error);
}

}  // namespace
}  // namespace omnidso
