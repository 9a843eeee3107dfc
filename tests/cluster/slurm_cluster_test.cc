// `omnidso ablate --executor slurm` against a real Slurm started on this machine (label
// `slow`; `make test-slurm` installs Slurm and runs it; skipped with the reason when Slurm is
// not installed). A tiny rendered sequence (30 frames, 120×120), one camera model, N_f 5 and
// 3, two seeds: four `omnidso run`s, deterministic (--threads 1). The same grid runs once with the
// local executor and once through Slurm, where array task 0 is cancelled (scancel) while it runs:
// the run must be reported failed with Slurm's reason, a second submission must run only it,
// and then Tables I–IV and every run's RMSE must equal the local executor's bit for bit.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/temp_dir.hpp"
#include "local_slurm.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

double seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// runs.csv without its measured columns (timing, wall time): what must not depend on who ran it.
std::string runsWithoutTimes(const std::string& path) {
  std::string kept, line;
  std::ifstream in(path);
  while (std::getline(in, line)) {
    std::vector<std::string> f(1);
    for (char c : line) c == ',' ? void(f.emplace_back()) : f.back().push_back(c);
    for (size_t i = 0; i < f.size(); ++i)
      if (i != 9 && i != 10 && i != 11) kept += f[i] + ",";  // tracking, mapping, wall_s
    kept += "\n";
  }
  return kept;
}

TEST(SlurmClusterTest, AblationThroughSlurmEqualsTheLocalOneAndACancelledTaskIsRunAgain) {
  const std::string unavailable = test::LocalSlurm::unavailableReason();
  if (!unavailable.empty()) GTEST_SKIP() << "no local Slurm: " << unavailable;
  test::TempDir dir;
  const std::string omnidso = OMNIDSO_EXECUTABLE;
  const std::string data = dir.file("room");
  ASSERT_EQ(std::system((omnidso +
                         " synth --preset room185 --frames 30 --size 120x120 --quiet "
                         "--out " +
                         data + " > /dev/null")
                            .c_str()),
            0);
  const std::string grid =
      omnidso + " ablate --datasets " + data +
      " --camera-models native --keyframes 5,3 --runs 2 --threads 1 --points 600"
      " --timeout 600 --quiet";
  const std::string local = dir.file("local"), cluster = dir.file("cluster");
  Clock::time_point start = Clock::now();
  ASSERT_EQ(std::system((grid + " --jobs 2 --out " + local + " > /dev/null 2>&1").c_str()), 0);
  const double local_s = seconds(start);

  test::LocalSlurm slurm;
  // Submitted and followed in the background; task 0 is cancelled once its run has started.
  const std::string submit = grid + " --executor slurm --jobs 2 --poll-interval 0.5 --out " +
                             cluster + " > " + dir.file("first.log") + " 2>&1";
  int first_status = -1;
  start = Clock::now();
  std::thread first([&] { first_status = std::system(submit.c_str()); });
  const std::string run0 = cluster + "/runs/room__native__kf5/run1";
  std::string job;
  while (seconds(start) < 120 && (job.empty() || !fs::exists(run0 + "/log.txt"))) {
    job = readFile(cluster + "/slurm/submission-1/job_id");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  job = job.substr(0, job.find('\n'));
  ASSERT_FALSE(job.empty()) << readFile(dir.file("first.log"));
  EXPECT_EQ(std::system(("scancel " + job + "_0").c_str()), 0);
  first.join();
  const double first_s = seconds(start);
  ASSERT_EQ(first_status, 0) << readFile(dir.file("first.log"));
  EXPECT_FALSE(fs::exists(run0 + "/result.json")) << "cancelled while running";
  const std::string runs = readFile(cluster + "/runs.csv");
  EXPECT_NE(runs.find("room,native,5,1,0,failed,\"Slurm: CANCELLED by 0 (job " + job + "_0"),
            std::string::npos)
      << runs << readFile(dir.file("first.log"));
  EXPECT_NE(readFile(cluster + "/tables.md").find("(failed 1/2)"), std::string::npos);
  // --collect on the folder says the same without asking Slurm again.
  ASSERT_EQ(std::system((omnidso + " ablate --collect --out " + cluster + " > /dev/null").c_str()),
            0);
  EXPECT_EQ(readFile(cluster + "/runs.csv"), runs);

  // Resubmitted: one array task, the cancelled run; then the tables equal the local ones.
  start = Clock::now();
  ASSERT_EQ(std::system((grid + " --executor slurm --poll-interval 0.5 --out " + cluster + " > " +
                         dir.file("second.log") + " 2>&1")
                            .c_str()),
            0)
      << readFile(dir.file("second.log"));
  const double second_s = seconds(start);
  const std::string script = readFile(cluster + "/slurm/submission-2/job.sh");
  EXPECT_NE(script.find("#SBATCH --array=0-0\n"), std::string::npos) << script;
  EXPECT_NE(script.find(run0 + " -- "), std::string::npos) << script;
  for (const char* table : {"table1_rmse.csv", "table2_length.csv", "table3_rmse_per_keyframes.csv",
                            "table4_rmse_differences.csv"})
    EXPECT_EQ(readFile(cluster + "/" + table), readFile(local + "/" + table)) << table;
  EXPECT_EQ(runsWithoutTimes(cluster + "/runs.csv"), runsWithoutTimes(local + "/runs.csv"));
  for (const char* run : {"kf5/run1", "kf5/run2", "kf3/run1", "kf3/run2"}) {  // every bit
    const std::string result = std::string("/runs/room__native__") + run + "/result.json";
    const auto a = nlohmann::json::parse(readFile(local + result));
    const auto b = nlohmann::json::parse(readFile(cluster + result));
    EXPECT_EQ(a["status"], "ok") << run;
    EXPECT_EQ(a["rmse_m"], b["rmse_m"]) << run;
    EXPECT_EQ(a["settings"], b["settings"]) << run;
  }
  const std::string sacct =
      test::commandOutput("sacct -n -X -P -j " + job + " -o JobID,State,Elapsed");
  std::cout << "local executor: 4 runs in " << local_s << " s; Slurm: first submission " << first_s
            << " s (task 0 cancelled), resubmission of 1 run " << second_s << " s\n"
            << "sacct:\n"
            << sacct;
}

}  // namespace
}  // namespace omnidso
