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

}  // namespace
}  // namespace omnidso
