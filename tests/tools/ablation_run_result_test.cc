// Which runs of an ablation count as failed, and their result.json for resuming.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/core/error.hpp>

#include "synth_test_util.hpp"

namespace omnidso::cli {
namespace {

nlohmann::json goodSummary() {
  return nlohmann::json::parse(R"({
    "initialized": true, "counts": {"segments": 1},
    "events": ["segment 0: initialised at frame 4 from frame 0"],
    "timing": {"tracking_ms_per_frame": {"mean": 12.5}, "mapping_ms_per_keyframe": {"mean": 150}},
    "ate": {"segment": 0, "keyframe_ate": {"rmse_m": 0.02, "rmse_percent_of_path": 1.6}}})");
}

PlannedRun plannedRun(const std::string& directory) {
  PlannedRun run;
  run.run = 2;
  run.seed = 7;
  run.directory = directory;
  run.settings = {{"dataset", "seq"}, {"seed", 7}, {"points", 2000}};
  return run;
}

ProcessOutcome exited(int code) {
  ProcessOutcome o;
  o.kind = ProcessOutcome::Kind::kExited;
  o.exit_code = code;
  o.wall_s = 3;
  return o;
}

TEST(AblationRunResultTest, SummaryWithOneSegmentAndAnAteIsASuccess) {
  EXPECT_FALSE(summaryFailure(goodSummary()));
}

TEST(AblationRunResultTest, LostTrackingNoInitialisationAndNoAteAreFailures) {
  nlohmann::json s = goodSummary();
  s["counts"]["segments"] = 2;
  EXPECT_NE(summaryFailure(s).value_or("").find("lost tracking (2"), std::string::npos);
  s = goodSummary();
  s["events"].push_back("segment 0: tracking lost at frame 40; re-initialising");
  EXPECT_NE(summaryFailure(s).value_or("").find("lost tracking"), std::string::npos);
  s = goodSummary();
  s["initialized"] = false;
  s["initialization_status"] = "parallax 1 px of the 4.8 px needed";
  EXPECT_EQ(summaryFailure(s).value_or(""), "not initialised: parallax 1 px of the 4.8 px needed");
  s = goodSummary();
  s.erase("ate");
  EXPECT_TRUE(summaryFailure(s));
  s = goodSummary();
  s["ate"]["keyframe_ate"] = {{"error", "too few poses"}};
  EXPECT_EQ(summaryFailure(s).value_or(""), "no keyframe ATE: too few poses");
}

TEST(AblationRunResultTest, ClassifiesProcessFailuresWithTheLastLogLine) {
  test::TempDir tmp("run_result_exit");
  std::ofstream(tmp.str() + "/log.txt") << "reading\nomnidso: error: seq: no images\n\n";
  const RunResult r = classifyRun(plannedRun(tmp.str()), exited(2));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.failure, "exit status 2: omnidso: error: seq: no images");
  EXPECT_EQ(r.seed, 7u);
  ProcessOutcome timeout;
  timeout.kind = ProcessOutcome::Kind::kTimedOut;
  timeout.error = "timeout after 60 s";
  EXPECT_EQ(classifyRun(plannedRun(tmp.str()), timeout).failure, "timeout after 60 s");
  // Exit status 0 without a summary is a failure too.
  EXPECT_FALSE(classifyRun(plannedRun(tmp.str()), exited(0)).ok);
}

TEST(AblationRunResultTest, ReadsTheMetricsOfASuccessfulRun) {
  test::TempDir tmp("run_result_ok");
  std::ofstream(tmp.str() + "/summary.json") << goodSummary().dump();
  const RunResult r = classifyRun(plannedRun(tmp.str()), exited(0));
  EXPECT_TRUE(r.ok) << r.failure;
  EXPECT_DOUBLE_EQ(r.rmse_m.value(), 0.02);
  EXPECT_DOUBLE_EQ(r.rmse_percent_of_path.value(), 1.6);
  EXPECT_DOUBLE_EQ(r.tracking_ms.value(), 12.5);
  EXPECT_DOUBLE_EQ(r.mapping_ms.value(), 150);
}

TEST(AblationRunResultTest, AFinishedRunIsReadBackAndOtherSettingsAreRefused) {
  test::TempDir tmp("run_result_resume");
  const PlannedRun run = plannedRun(tmp.str());
  EXPECT_FALSE(readFinishedRun(run));
  std::ofstream(tmp.str() + "/summary.json") << goodSummary().dump();
  const RunResult written = classifyRun(run, exited(0));
  writeRunResult(tmp.str(), written);
  EXPECT_FALSE(std::filesystem::exists(tmp.str() + "/result.json.tmp"));
  const std::optional<RunResult> read = readFinishedRun(run);
  ASSERT_TRUE(read);
  EXPECT_EQ(toJson(*read), toJson(written));

  PlannedRun other = run;
  other.settings["points"] = 1000;
  try {
    readFinishedRun(other);
    FAIL() << "settings differ";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("points 2000 there, 1000 now"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace omnidso::cli
