// The grid of `omnidso ablate`: cells, seeds, run arguments, option checks, --out handling.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <omnidso/cli/ablation_plan.hpp>
#include <omnidso/core/error.hpp>
#include <set>

#include "synth_test_util.hpp"

namespace omnidso::cli {
namespace {

AblationSpec exampleSpec() {
  AblationSpec spec;
  spec.datasets = {"data/seqA", "data/seqB/"};
  spec.camera_models = {"native", "pinhole-crop:90"};
  spec.keyframes = {7, 5, 3};
  spec.runs = 3;
  spec.base_seed = 10;
  return spec;
}

std::string errorOf(const AblationSpec& spec) {
  try {
    planAblation(spec, "out");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::vector<std::string>& args, const std::vector<std::string>& part) {
  return std::search(args.begin(), args.end(), part.begin(), part.end()) != args.end();
}

TEST(AblationPlanTest, EveryCombinationIsACellWithItsRuns) {
  const AblationPlan plan = planAblation(exampleSpec(), "out");
  ASSERT_EQ(plan.cells.size(), 2u * 2u * 3u);
  ASSERT_EQ(plan.runs.size(), plan.cells.size() * 3u);
  EXPECT_EQ(plan.cells[0].dataset_name, "seqA");
  EXPECT_EQ(plan.cells.back().dataset_name, "seqB");  // a trailing '/' does not change the name
  EXPECT_EQ(plan.cells[4].id(), "seqA__pinhole-crop-90__kf5");
  EXPECT_EQ(plan.cells[4].method(), "pinhole-crop:90 Kf5");
  std::set<std::string> directories;
  for (const PlannedRun& run : plan.runs) directories.insert(run.directory);
  EXPECT_EQ(directories.size(), plan.runs.size());
  EXPECT_EQ(plan.runs[5].directory, "out/runs/seqA__native__kf5/run3");
}

TEST(AblationPlanTest, SeedsDifferBetweenRunsAndAreSharedAcrossCells) {
  const AblationPlan plan = planAblation(exampleSpec(), "out");
  for (const PlannedRun& run : plan.runs) {
    EXPECT_EQ(run.seed, 10u + run.run - 1);
    EXPECT_TRUE(contains(run.arguments, {"--seed", std::to_string(run.seed)}));
    EXPECT_EQ(run.settings["seed"], run.seed);
  }
  std::set<std::uint64_t> seeds_of_first_cell;
  for (int k = 0; k < 3; ++k) seeds_of_first_cell.insert(plan.runs[k].seed);
  EXPECT_EQ(seeds_of_first_cell.size(), 3u);
}

TEST(AblationPlanTest, RunArgumentsCarryTheCellAndThePassThroughOptions) {
  AblationSpec spec = exampleSpec();
  spec.pass_through.points = 800;
  spec.pass_through.max_frames = 50;
  spec.pass_through.no_intrinsics_opt = true;
  spec.pass_through.no_vignette_estimation = true;
  spec.pass_through.settings = {"window.max_iterations=10", "epipolar.min_quality=4"};
  const AblationPlan plan = planAblation(spec, "out");
  const PlannedRun& run = plan.runs[4 * 3];  // cell 4: seqA, pinhole-crop:90, N_f 5
  const std::vector<std::string>& a = run.arguments;
  EXPECT_EQ(a[0], "run");
  EXPECT_TRUE(std::filesystem::path(a[1]).is_absolute());
  EXPECT_TRUE(contains(a, {"--out", run.directory}));
  EXPECT_TRUE(contains(a, {"--camera-model", "pinhole-crop:90"}));
  EXPECT_TRUE(contains(a, {"--keyframes", "5"}));
  EXPECT_TRUE(contains(a, {"--points", "800"}));
  EXPECT_TRUE(contains(a, {"--max-frames", "50"}));
  EXPECT_TRUE(contains(a, {"--no-intrinsics-opt"}));
  EXPECT_EQ(run.settings["optimize_intrinsics"], false);
  EXPECT_TRUE(contains(a, {"--no-vignette-estimation"}));
  EXPECT_EQ(run.settings["vignette_estimation"], false);
  // Left at its default the flag is not in the settings, which then match the runs of
  // ablations made before it existed (resume compares them).
  EXPECT_FALSE(planAblation(exampleSpec(), "out").runs[0].settings.contains("vignette_estimation"));
  // Odometry settings reach every run in order, and are part of what resume compares.
  EXPECT_TRUE(contains(a, {"--set", "window.max_iterations=10", "--set", "epipolar.min_quality=4"}));
  EXPECT_EQ(run.settings["settings"][1], "epipolar.min_quality=4");
}

TEST(AblationPlanTest, BadSpecsAreRefusedNamingTheOption) {
  AblationSpec spec = exampleSpec();
  spec.keyframes = {7, 7};
  EXPECT_NE(errorOf(spec).find("--keyframes: '7' is listed twice"), std::string::npos);
  spec = exampleSpec();
  spec.keyframes = {1};
  EXPECT_NE(errorOf(spec).find("--keyframes"), std::string::npos);
  spec = exampleSpec();
  spec.camera_models = {"fisheye"};
  EXPECT_NE(errorOf(spec).find("--camera-models"), std::string::npos);
  spec = exampleSpec();
  spec.runs = 0;
  EXPECT_NE(errorOf(spec).find("--runs"), std::string::npos);
  spec = exampleSpec();
  spec.datasets = {"a/seq", "b/seq"};
  EXPECT_NE(errorOf(spec).find("same name 'seq'"), std::string::npos);
  spec.datasets = {};
  EXPECT_NE(errorOf(spec).find("--datasets: the list is empty"), std::string::npos);
}

TEST(AblationPlanTest, ListsAreSplitOnCommasWithoutEmptyItems) {
  EXPECT_EQ(splitList("a,b,c", "--x"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(parseIntegerList("7,5,3", "--keyframes"), (std::vector<int>{7, 5, 3}));
  EXPECT_THROW(splitList("a,,b", "--x"), Error);
  EXPECT_THROW(splitList("", "--x"), Error);
  EXPECT_THROW(parseIntegerList("7,5x", "--keyframes"), Error);
}

TEST(AblationPlanTest, OutputDirectoryMustBeNewEmptyOrAnAblation) {
  test::TempDir tmp("ablation_out");
  const std::string fresh = tmp.str() + "/new";
  prepareAblationDirectory(fresh);
  EXPECT_TRUE(std::filesystem::is_directory(fresh));
  prepareAblationDirectory(fresh);  // empty: fine

  const std::string users = tmp.str() + "/users";
  std::filesystem::create_directories(users);
  std::ofstream(users + "/notes.txt") << "mine\n";
  EXPECT_THROW(prepareAblationDirectory(users), Error);
  EXPECT_THROW(prepareAblationDirectory(users + "/notes.txt"), Error);

  std::ofstream(fresh + "/" + kAblationMarker) << "{}\n";
  std::filesystem::create_directories(fresh + "/runs");
  prepareAblationDirectory(fresh);  // an earlier ablation: resumed
}

}  // namespace
}  // namespace omnidso::cli
