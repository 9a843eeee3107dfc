// `omnidso eval` on files with the field's quirks, run as the executable: a TUM RGB-D style
// ground truth whose motion-capture export repeats a timestamp (fr2/desk, line 10863) must
// evaluate, as evo evaluates it. evo associates every estimated stamp with the ground-truth
// stamp of least |Δt| (numpy argmin: the first of equal stamps), so its figures are those of
// the ground truth with the later duplicates removed — here an estimate equal to the first
// poses has ATE 0, while keeping a later duplicate would give an error of 7 m at that pose.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include <omnidso/cli/process_pool.hpp>

#include "bad_input_fixtures.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;

struct EvalRun {
  cli::ProcessOutcome outcome;
  std::string output;  // stderr (warnings, first) and stdout
};

EvalRun runEval(const fs::path& dir, const std::vector<std::string>& arguments) {
  cli::ProcessSpec spec;
  spec.argv = {OMNIDSO_EXECUTABLE, "eval"};
  spec.argv.insert(spec.argv.end(), arguments.begin(), arguments.end());
  spec.log_path = (dir / "eval.log").string();
  spec.timeout_s = 60;
  EvalRun run{cli::runProcesses({spec}, 1).front(), ""};
  run.output = test::readBytes(spec.log_path);
  return run;
}

TEST(EvalTolerance, RepeatedGroundTruthTimestampEvaluatesLikeEvo) {
  const fs::path dir = test::BadInputFixtures::get().caseRoot("eval_repeated_stamp");
  // TUM RGB-D's header, CRLF ends, scientific notation, and line 6 repeating line 5's stamp.
  test::writeBytes(dir / "gt.txt",
                   "# ground truth trajectory\r\n# file: 'rgbd_dataset_freiburg2_desk.bag'\r\n"
                   "# timestamp tx ty tz qx qy qz qw\r\n"
                   "1311868229.5460 0 0 0 0 0 0 1\r\n"
                   "1311868229.5760 2 0 0 0 0 0 1\r\n"
                   "1311868229.5760 9 0 0 0 0 0 1\r\n"
                   "1.3118682296060E+09 3 1 0 0 0 0 1\r\n"
                   "1311868229.6360 4 1 1 0 0 0 1\r\n");
  // The estimate lists the same poses, out of order.
  test::writeBytes(dir / "est.txt",
                   "1311868229.6360 4 1 1 0 0 0 1\n1311868229.5460 0 0 0 0 0 0 1\n"
                   "1311868229.5760 2 0 0 0 0 0 1\n1311868229.6060 3 1 0 0 0 0 1\n");
  const std::vector<std::string> arguments = {
      "--gt", (dir / "gt.txt").string(), "--est", (dir / "est.txt").string(), "--align", "none",
      "--json"};
  const EvalRun run = runEval(dir, arguments);
  ASSERT_TRUE(run.outcome.succeeded()) << run.outcome.describe() << "\n" << run.output;
  EXPECT_NE(run.output.find("warning: " + (dir / "gt.txt").string() +
                            ": 1 pose(s) with a repeated timestamp dropped"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("warning: " + (dir / "est.txt").string() + ": lines are not in time order"),
            std::string::npos)
      << run.output;
  const nlohmann::json result = nlohmann::json::parse(run.output.substr(run.output.find('{')));
  EXPECT_EQ(result["gt_poses"], 4);
  EXPECT_EQ(result["matched_poses"], 4);
  // Identical poses: only the rounding of the JSON print remains.
  EXPECT_LT(result["ate"]["rmse"].get<double>(), 1e-12);

  std::vector<std::string> strict = arguments;
  strict.push_back("--strict");
  const EvalRun refused = runEval(dir, strict);
  EXPECT_EQ(refused.outcome.exit_code, 2) << refused.output;
  EXPECT_NE(refused.output.find("omnidso: error: " + (dir / "gt.txt").string() + ":6: "),
            std::string::npos)
      << refused.output;
}

// KITTI poses carry no timestamps. An estimate of keyframes only (TUM, stamped) against KITTI's
// poses/NN.txt paired by line matched keyframe k with frame k — a silently wrong ATE (here
// 0.82 m). Without the times that is refused; with KITTI's times.txt the poses are matched by
// time.
TEST(EvalTolerance, KittiGroundTruthIsMatchedByItsTimesNotByLine) {
  const fs::path dir = test::BadInputFixtures::get().caseRoot("eval_kitti_times");
  // Four frames moving 1 m along x each, 0.1 s apart.
  test::writeBytes(dir / "poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n"
                                      "1 0 0 2 0 1 0 0 0 0 1 0\n1 0 0 3 0 1 0 0 0 0 1 0\n");
  test::writeBytes(dir / "times.txt", "0.000000e+00\n1.000000e-01\n2.000000e-01\n3.000000e-01\n");
  // Keyframes: frames 0, 2 and 3.
  test::writeBytes(dir / "keyframes.txt",
                   "0.0 0 0 0 0 0 0 1\n0.2 2 0 0 0 0 0 1\n0.3 3 0 0 0 0 0 1\n");
  const std::vector<std::string> arguments = {
      "--gt", (dir / "poses.txt").string(), "--gt-format", "kitti",
      "--est", (dir / "keyframes.txt").string(), "--align", "none", "--json"};
  const EvalRun by_line = runEval(dir, arguments);
  EXPECT_EQ(by_line.outcome.exit_code, 2) << by_line.output;
  EXPECT_NE(by_line.output.find("--kitti-times"), std::string::npos) << by_line.output;

  std::vector<std::string> timed = arguments;
  timed.insert(timed.end(), {"--kitti-times", (dir / "times.txt").string()});
  const EvalRun run = runEval(dir, timed);
  ASSERT_TRUE(run.outcome.succeeded()) << run.outcome.describe() << "\n" << run.output;
  const nlohmann::json result = nlohmann::json::parse(run.output.substr(run.output.find('{')));
  EXPECT_EQ(result["matched_poses"], 3);
  // The keyframes are the ground truth's poses at their times: only rounding remains.
  EXPECT_LT(result["ate"]["rmse"].get<double>(), 1e-12);

  // A times.txt of another length names both files.
  test::writeBytes(dir / "short_times.txt", "0.0\n0.1\n");
  timed.back() = (dir / "short_times.txt").string();
  const EvalRun mismatch = runEval(dir, timed);
  EXPECT_EQ(mismatch.outcome.exit_code, 2) << mismatch.output;
  EXPECT_NE(mismatch.output.find("4 poses, but " + (dir / "short_times.txt").string() +
                                 " lists 2 timestamps"),
            std::string::npos)
      << mismatch.output;
}

}  // namespace
}  // namespace omnidso
