// `omnidso ablate` in-process on a tiny rendered dataset, with a shell script standing in for
// `omnidso run` (--omnidso), so that successes, failures and resuming are known exactly.
#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <omnidso/cli/commands.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/synth/dataset_writer.hpp>

#include "ablate_test_util.hpp"
#include "synth_test_util.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;

void runAblate(const std::string& arguments) {
  CLI::App app;
  app.require_subcommand(1);
  cli::registerAblateCommand(app);
  app.parse("ablate --quiet " + arguments);
}

class AblateCommandTest : public ::testing::Test {
 protected:
  AblateCommandTest() : tmp_("ablate_command") {
    synth::SyntheticSequence sequence(test::smallSequenceConfig(6));
    synth::writeSyntheticDataset(sequence, tmp_.str() + "/seq");
    fake_ = tmp_.str() + "/fake_run.sh";
    std::ofstream(fake_) << test::kFakeRun;
    ::chmod(fake_.c_str(), 0755);
  }
  std::string arguments(const std::string& out, int runs = 2) const {
    return "--datasets " + tmp_.str() +
           "/seq --camera-models native,pinhole-crop:90 "
           "--keyframes 5,3 --jobs 2 --omnidso " +
           fake_ + " --out " + out + " --runs " + std::to_string(runs);
  }
  test::TempDir tmp_;
  std::string fake_;
};

TEST_F(AblateCommandTest, WritesEveryTableAndPlotAndMarksFailedRuns) {
  const std::string out = tmp_.str() + "/ablation";
  runAblate(arguments(out));
  EXPECT_EQ(test::lineCount(tmp_.str() + "/calls.txt"), 8u);  // 4 cells × 2 runs
  for (const char* file :
       {"tables.md", "table1_rmse.csv", "table2_length.csv", "table3_rmse_per_keyframes.csv",
        "table4_rmse_differences.csv", "table5_timing.csv", "runs.csv", "ablation.json",
        "plots/seq_trajectories.png", "plots/seq_ate.png"})
    EXPECT_TRUE(fs::is_regular_file(out + "/" + file)) << file;
  EXPECT_EQ(test::lineCount(out + "/runs.csv"), 1u + 8u);
  EXPECT_TRUE(fs::is_regular_file(out + "/runs/seq__pinhole-crop-90__kf3/run2/log.txt"));

  const std::string md = test::readFile(out + "/tables.md");
  EXPECT_NE(md.find("| seq     | native          |  0.0150 | 0.0100 (failed 1/2) |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("failed 2/2"), std::string::npos) << md;
  EXPECT_NE(md.find("exit status 3: omnidso: error: fake failure"), std::string::npos) << md;
  EXPECT_NE(md.find("lost tracking (2 trajectory segments)"), std::string::npos) << md;
  const std::string runs = test::readFile(out + "/runs.csv");
  EXPECT_NE(runs.find("seq,native,3,2,1,failed,lost tracking"), std::string::npos) << runs;
}

TEST_F(AblateCommandTest, ASecondInvocationRunsNothingAgain) {
  const std::string out = tmp_.str() + "/ablation";
  runAblate(arguments(out));
  const std::string tables = test::readFile(out + "/tables.md");
  runAblate(arguments(out));
  EXPECT_EQ(test::lineCount(tmp_.str() + "/calls.txt"), 8u);
  EXPECT_EQ(test::readFile(out + "/tables.md"), tables);
  // A third run per cell is new work: only those 4 runs.
  runAblate(arguments(out, 3));
  EXPECT_EQ(test::lineCount(tmp_.str() + "/calls.txt"), 12u);
  // Other settings than the finished runs': refused, nothing run.
  EXPECT_THROW(runAblate(arguments(out) + " --points 500"), Error);
  EXPECT_EQ(test::lineCount(tmp_.str() + "/calls.txt"), 12u);
}

TEST_F(AblateCommandTest, RefusesADirectoryThatIsNotAnAblation) {
  const std::string out = tmp_.str() + "/mine";
  fs::create_directories(out);
  std::ofstream(out + "/notes.txt") << "keep\n";
  EXPECT_THROW(runAblate(arguments(out)), Error);
  EXPECT_EQ(test::readFile(out + "/notes.txt"), "keep\n");
  EXPECT_FALSE(fs::exists(tmp_.str() + "/calls.txt"));
}

}  // namespace
}  // namespace omnidso
