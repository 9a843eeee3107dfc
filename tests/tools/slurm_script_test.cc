// The job-array script of --executor slurm: its #SBATCH lines, and that array task i runs
// exactly the i-th command line (run by bash, as slurmd runs it).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <omnidso/cli/slurm_script.hpp>
#include <omnidso/core/error.hpp>

#include "core/temp_dir.hpp"

namespace omnidso {
namespace {

std::string outputOf(const std::string& command) {
  FILE* pipe = ::popen(command.c_str(), "r");
  std::string out;
  for (int c = std::fgetc(pipe); c != EOF; c = std::fgetc(pipe))
    out.push_back(static_cast<char>(c));
  ::pclose(pipe);
  return out;
}

const std::vector<std::vector<std::string>> kTasks = {
    {"/bin/echo", "run 0", "it's"}, {"/bin/echo", "run", "1"}, {"/bin/echo", "$2"}};

TEST(SlurmScriptTest, HasOneArrayTaskPerRunAndTheRequestedResources) {
  cli::SlurmResources r;
  r.partition = "gpu";
  r.time = "1:00:00";
  r.cpus = 4;
  r.mem = "8G";
  r.extra = {"--account=vision", "--qos=short"};
  const std::string s = cli::slurmArrayScript(kTasks, r, 2, "/scratch/out/slurm/submission-1");
  EXPECT_EQ(s.rfind("#!/bin/bash\n", 0), 0u);
  for (const char* line :
       {"#SBATCH --array=0-2%2\n", "#SBATCH --output=/scratch/out/slurm/submission-1/task-%a.out\n",
        "#SBATCH --cpus-per-task=4\n", "#SBATCH --partition=gpu\n", "#SBATCH --time=1:00:00\n",
        "#SBATCH --mem=8G\n", "#SBATCH --account=vision\n", "#SBATCH --qos=short\n",
        "#SBATCH --ntasks=1\n"})
    EXPECT_NE(s.find(line), std::string::npos) << line << "\n" << s;
  // Without a limit there is no %M; unset resources have no line.
  const std::string plain = cli::slurmArrayScript(kTasks, {}, 0, "/o/100%/s");
  EXPECT_NE(plain.find("#SBATCH --array=0-2\n"), std::string::npos) << plain;
  EXPECT_NE(plain.find("--output=/o/100%%/s/task-%a.out"), std::string::npos) << plain;
  EXPECT_EQ(plain.find("--partition"), std::string::npos);
  EXPECT_EQ(plain.find("--mem"), std::string::npos);
}

TEST(SlurmScriptTest, TaskIRunsTheIthCommandLineAndAnUnknownTaskFails) {
  test::TempDir dir;
  const std::string path = dir.file("job.sh");
  std::ofstream(path) << cli::slurmArrayScript(kTasks, {}, 0, dir.file("x"));
  EXPECT_EQ(outputOf("SLURM_ARRAY_TASK_ID=0 bash " + path), "run 0 it's\n");
  EXPECT_EQ(outputOf("SLURM_ARRAY_TASK_ID=1 bash " + path), "run 1\n");
  EXPECT_EQ(outputOf("SLURM_ARRAY_TASK_ID=2 bash " + path + " a b"), "$2\n");
  EXPECT_NE(std::system(("SLURM_ARRAY_TASK_ID=3 bash " + path + " 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system(("bash " + path + " 2>/dev/null").c_str()), 0) << "not an array task";
}

TEST(SlurmScriptTest, RefusesWhatAnSbatchLineCannotHold) {
  cli::SlurmResources r;
  r.extra = {"--account=a\n#SBATCH --mem=1T"};
  EXPECT_THROW(cli::slurmArrayScript(kTasks, r, 0, "/o"), Error);
  EXPECT_THROW(cli::slurmArrayScript(kTasks, {}, 0, "/my results/s"), Error);
  EXPECT_THROW(cli::slurmArrayScript({}, {}, 0, "/o"), Error);
}

}  // namespace
}  // namespace omnidso
