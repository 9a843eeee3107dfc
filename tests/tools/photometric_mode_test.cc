// The photometric model chosen by the data (cli::applyPhotometricMode): with every frame's
// exposure time the window ties each keyframe's affine brightness to 0; without them the gain
// goes free (auto-exposure is what the affine model must explain) and the offset stays tied.
// And the window's solve and the tracking reference's depth check chosen by the view's width
// (cli::applyViewProfile, cli::applyNarrowViewTracking). The user's settings still win.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>

#include <omnidso/cli/dataset_runner.hpp>
#include <omnidso/cli/process_pool.hpp>
#include <omnidso/synth/dataset_writer.hpp>

#include "synth_test_util.hpp"

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

DatasetIndex indexWithExposures(std::vector<double> exposures_ms) {
  DatasetIndex index;
  for (size_t i = 0; i < exposures_ms.size(); ++i) {
    DatasetFrame f;
    f.id = std::to_string(i);
    f.timestamp_s = 0.05 * static_cast<double>(i);
    f.exposure_ms = exposures_ms[i];
    index.frames.push_back(f);
  }
  return index;
}

TEST(PhotometricMode, ExposureTimesKeepTheWindowsTies) {
  OdometryOptions options;
  const OdometryOptions defaults;
  EXPECT_TRUE(exposureTimesKnown(indexWithExposures({6.4, 6.5, 15.7})));
  EXPECT_EQ(applyPhotometricMode(indexWithExposures({6.4, 6.5, 15.7}), &options), "");
  EXPECT_EQ(options.window.affine_prior_weight_a, defaults.window.affine_prior_weight_a);
  EXPECT_EQ(options.window.affine_prior_weight_b, defaults.window.affine_prior_weight_b);
  EXPECT_GT(options.window.affine_prior_weight_a, 0.0);
}

TEST(PhotometricMode, WithoutExposureTimesTheGainIsFreeAndTheOffsetTied) {
  OdometryOptions options;
  const OdometryOptions defaults;
  ASSERT_GT(defaults.window.affine_prior_weight_b, 0.0);
  ASSERT_GT(defaults.tracker.affine_prior_weight_b, 0.0);
  ASSERT_FALSE(defaults.tracker.affine_in_reference_gauge);
  const std::string note = applyPhotometricMode(indexWithExposures({0, 0, 0}), &options);
  EXPECT_NE(note.find("no exposure times"), std::string::npos) << note;
  // The gain free in the window and in the tracker …
  EXPECT_EQ(options.window.affine_prior_weight_a, 0.0);
  EXPECT_EQ(options.tracker.affine_prior_weight_a, 0.0);
  // … the offset tied to 0 in both, the tracker's about black.
  EXPECT_EQ(options.window.affine_prior_weight_b, defaults.window.affine_prior_weight_b);
  EXPECT_EQ(options.tracker.affine_prior_weight_b, defaults.tracker.affine_prior_weight_b);
  EXPECT_TRUE(options.tracker.affine_in_reference_gauge);
  // The initialiser's tie (to the segment's first frame) stays.
  EXPECT_EQ(options.initializer.affine_prior_weight_a, defaults.initializer.affine_prior_weight_a);
}

TEST(PhotometricMode, OneMissingExposureTimeMakesThemUnknown) {
  // dataset_runner feeds an unknown exposure as 1 ms: next to known ones the exposure ratio
  // would be wrong by orders of magnitude, so only the free affine model can be trusted.
  EXPECT_FALSE(exposureTimesKnown(indexWithExposures({6.4, 0, 6.5})));
  EXPECT_FALSE(exposureTimesKnown(DatasetIndex{}));
}

// `omnidso run DATA --out DIR/NAME --quiet EXTRA…`, expected to succeed: its summary.json and
// what it printed.
std::pair<nlohmann::json, std::string> runOmnidso(const fs::path& data, const fs::path& dir,
                                                  const std::string& name,
                                                  const std::vector<std::string>& extra) {
  ProcessSpec spec;
  spec.argv = {OMNIDSO_EXECUTABLE, "run", data.string(), "--out", (dir / name).string(), "--quiet"};
  spec.argv.insert(spec.argv.end(), extra.begin(), extra.end());
  spec.log_path = (dir / (name + ".log")).string();
  spec.timeout_s = 120;
  const ProcessOutcome outcome = runProcesses({spec}, 1).front();
  std::ifstream log(spec.log_path);
  const std::string output((std::istreambuf_iterator<char>(log)), {});
  EXPECT_TRUE(outcome.succeeded()) << name << ": " << outcome.describe() << "\n" << output;
  return {nlohmann::json::parse(std::ifstream(dir / name / "summary.json")), output};
}

// As `omnidso run` applies it: the mode and the photometric files used are in summary.json's
// settings, and --set overrides the mode.
TEST(PhotometricMode, RunRecordsTheModeAndTheUsersSettingWins) {
  test::TempDir tmp("photometric_mode");
  const fs::path data = tmp.path() / "data";
  synth::SyntheticSequence sequence(test::smallSequenceConfig(3));
  synth::writeSyntheticDataset(sequence, data.string());
  // Drop times.txt's exposure column (comment lines stay).
  std::ifstream in(data / "times.txt");
  std::stringstream stripped;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') {
      stripped << line << "\n";
      continue;
    }
    std::istringstream fields(line);
    std::string id, stamp;
    fields >> id >> stamp;
    stripped << id << " " << stamp << "\n";
  }
  in.close();
  std::ofstream(data / "times.txt") << stripped.str();

  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    const auto [summary, output] = runOmnidso(data, tmp.path(), name, extra);
    // What the run had to work with: no exposure times, the rendered pcalib.txt and vignette.
    const nlohmann::json& photometric = summary.at("settings").at("photometric");
    EXPECT_FALSE(photometric.at("exposure_times").get<bool>());
    EXPECT_EQ(fs::path(photometric.at("inverse_response").get<std::string>()).filename(),
              "pcalib.txt");
    EXPECT_EQ(fs::path(photometric.at("vignette").get<std::string>()).filename(), "vignette.png");
    return std::make_pair(summary.at("settings").at("odometry"), output);
  };
  const auto [free, free_log] = run("free", {});
  EXPECT_EQ(free.at("window.affine_prior_weight_a").get<double>(), 0.0);
  EXPECT_EQ(free.at("window.affine_prior_weight_b").get<double>(), 1e6);
  EXPECT_EQ(free.at("tracker.affine_prior_weight_a").get<double>(), 0.0);
  EXPECT_TRUE(free.at("tracker.affine_in_reference_gauge").get<bool>());
  EXPECT_NE(free_log.find("no exposure times"), std::string::npos) << free_log;
  const auto [tied, tied_log] =
      run("tied", {"--set", "window.affine_prior_weight_a=1e8", "--set",
                   "tracker.affine_prior_weight_a=1e8", "--set",
                   "tracker.affine_in_reference_gauge=false"});
  EXPECT_EQ(tied.at("window.affine_prior_weight_a").get<double>(), 1e8);
  EXPECT_EQ(tied.at("tracker.affine_prior_weight_a").get<double>(), 1e8);
  EXPECT_FALSE(tied.at("tracker.affine_in_reference_gauge").get<bool>());
  EXPECT_EQ(tied_log.find("no exposure times"), std::string::npos) << tied_log;
}

// Without vignette.png `omnidso run` estimates one from the frames (dataset_vignette.hpp) and
// says what came of it; `--no-vignette-estimation` assumes none. Three 96-pixel frames hold
// far fewer tracks than an estimate needs, so the run records the attempt and why it gave
// nothing (the estimator's accuracy is vignette_estimation_test.cc's).
TEST(VignetteEstimate, RunRecordsTheAttemptAndTheFlagSkipsIt) {
  test::TempDir tmp("vignette_estimate");
  const fs::path data = tmp.path() / "data";
  synth::SyntheticSequence sequence(test::smallSequenceConfig(3));
  synth::writeSyntheticDataset(sequence, data.string());
  fs::remove(data / "vignette.png");
  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    const auto [summary, output] = runOmnidso(data, tmp.path(), name, extra);
    const nlohmann::json photometric = summary.at("settings").at("photometric");
    EXPECT_TRUE(photometric.at("vignette").is_null());
    return std::make_pair(photometric.at("vignette_estimate"), output);
  };
  const auto [tried, tried_log] = run("estimated", {});
  ASSERT_TRUE(tried.is_object()) << tried.dump();
  EXPECT_FALSE(tried.at("valid").get<bool>());
  EXPECT_EQ(tried.at("pairs").get<int>(), 2);  // frames 0–1 and 1–2
  EXPECT_NE(tried.at("reason").get<std::string>().find("needed"), std::string::npos);
  EXPECT_NE(tried_log.find("no vignette.png, and none could be estimated"), std::string::npos)
      << tried_log;
  EXPECT_FALSE(fs::exists(tmp.path() / "estimated" / "vignette_estimated.png"));
  const auto [skipped, skipped_log] = run("skipped", {"--no-vignette-estimation"});
  EXPECT_TRUE(skipped.is_null()) << skipped.dump();
  EXPECT_EQ(skipped_log.find("vignette"), std::string::npos) << skipped_log;
}

// A pinhole crop lays the residual pattern on the source's pixels: the spread is the crop's
// magnification at its centre, rounded — 240 · 2.05 / 190 = 2.59 → 3 for a 90° crop of a
// 480-pixel unified fisheye (f 190, ξ 1.05), 415.7 · 2.05 / 190 = 4.49 → 4 for a 60° one — and
// other models keep DSO's pattern.
TEST(CropPatternSpread, FollowsTheCropsMagnification) {
  const fs::path dir = fs::temp_directory_path() / "omnidso_crop_pattern_spread";
  fs::create_directories(dir);
  const fs::path calib = dir / "camera.txt";
  std::ofstream(calib) << "UCM 190 190 239.5 239.5 1.05\n480 480\nnone\n480 480\n";
  DatasetRunOptions run;
  run.calib = calib.string();
  DatasetIndex index = indexWithExposures({10.0});
  index.width = index.height = 480;
  for (const auto& [model, spread] :
       std::vector<std::pair<std::string, int>>{{"pinhole-crop:90", 3}, {"pinhole-crop:60", 4}}) {
    run.camera_model = model;
    OdometryOptions options;
    const std::string note = applyCropPatternSpread(index, run, &options);
    EXPECT_EQ(options.pattern_spread, spread) << model;
    EXPECT_NE(note.find("steps of " + std::to_string(spread) + " pixels"), std::string::npos)
        << note;
  }
  run.camera_model = "native";
  OdometryOptions options;
  EXPECT_EQ(applyCropPatternSpread(index, run, &options), "");
  EXPECT_EQ(options.pattern_spread, 1);
  fs::remove_all(dir);
}

// A narrow view with exposure times solves its window on central differences with three
// iterations; from 115° on (a 120° lens's image circle reads 119.98°), and without exposure
// times, the defaults stay. The widths themselves are viewWidthDeg's
// (intrinsics_prior_rule_test.cc).
TEST(ViewProfile, OnlyANarrowViewWithExposureTimesChangesTheWindow) {
  const OdometryOptions defaults;
  auto expectDefaults = [&](double width_deg, bool exposure_times) {
    OdometryOptions options;
    EXPECT_EQ(applyViewProfile(width_deg, exposure_times, &options), "") << width_deg;
    EXPECT_EQ(options.window.central_difference_gradients,
              defaults.window.central_difference_gradients);
    EXPECT_EQ(options.window.max_iterations, defaults.window.max_iterations);
  };
  expectDefaults(kNarrowViewBelowDeg, true);
  expectDefaults(119.98, true);
  expectDefaults(221.0, true);
  expectDefaults(109.47, false);
  OdometryOptions narrow;
  const std::string note = applyViewProfile(109.47, true, &narrow);
  EXPECT_TRUE(narrow.window.central_difference_gradients);
  EXPECT_EQ(narrow.window.max_iterations, 3);
  EXPECT_NE(note.find("109.5° across its widest, under 115°"), std::string::npos) << note;
  EXPECT_NE(note.find("--set window.max_iterations=" +
                      std::to_string(defaults.window.max_iterations)),
            std::string::npos)
      << note;
  // Nothing else of the window, the tracker or activation moves.
  EXPECT_FALSE(narrow.tracker.central_difference_gradients);
  EXPECT_FALSE(narrow.activation.central_difference_gradients);
  EXPECT_EQ(narrow.window.max_keyframes, defaults.window.max_keyframes);
  EXPECT_EQ(narrow.window.intrinsics_prior_weight, defaults.window.intrinsics_prior_weight);
}

// A narrow view's tracker aligns only the reference points whose inverse distance agrees with
// their neighbours', with or without exposure times; from 115° on every point is aligned.
TEST(NarrowViewTracking, OnlyANarrowViewChecksTheReferenceDepths) {
  const OdometryOptions defaults;
  ASSERT_EQ(defaults.reference_depths.neighbours, 0);  // the library's default: every point
  for (double width_deg : {kNarrowViewBelowDeg, 119.98, 221.0}) {
    OdometryOptions options;
    EXPECT_EQ(applyNarrowViewTracking(width_deg, &options), "") << width_deg;
    EXPECT_EQ(options.reference_depths.neighbours, 0) << width_deg;
  }
  OdometryOptions narrow;
  const std::string note = applyNarrowViewTracking(109.47, &narrow);
  EXPECT_EQ(narrow.reference_depths.neighbours, 8);
  EXPECT_EQ(narrow.reference_depths.max_log_deviation, defaults.reference_depths.max_log_deviation);
  EXPECT_NE(note.find("109.5° across its widest, under 115°"), std::string::npos) << note;
  EXPECT_NE(note.find("--set reference_depths.neighbours=0"), std::string::npos) << note;
  // The window's solve is applyViewProfile's, not this one's.
  EXPECT_EQ(narrow.window.max_iterations, defaults.window.max_iterations);
  EXPECT_EQ(narrow.window.central_difference_gradients,
            defaults.window.central_difference_gradients);
}

// As `omnidso run` applies them: summary.json records the view, the crop's window takes the
// narrow view's solve and its tracker the reference check, and the user's setting wins (and
// silences its note).
TEST(ViewProfile, RunRecordsTheViewAndTheUsersSettingWins) {
  test::TempDir tmp("view_profile_run");
  const fs::path data = tmp.path() / "data";
  synth::SyntheticSequence sequence(test::smallSequenceConfig(3));
  synth::writeSyntheticDataset(sequence, data.string());
  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    const auto [summary, output] = runOmnidso(data, tmp.path(), name, extra);
    return std::make_tuple(summary.at("settings").at("view"), summary.at("settings").at("odometry"),
                           output);
  };
  const auto [fisheye_view, fisheye, fisheye_log] = run("fisheye", {});
  EXPECT_FALSE(fisheye_view.at("narrow").get<bool>());
  EXPECT_FALSE(fisheye_view.at("narrow_view_window").get<bool>());
  EXPECT_FALSE(fisheye_view.at("narrow_view_tracking").get<bool>());
  EXPECT_EQ(fisheye.at("reference_depths.neighbours").get<int>(), 0);
  EXPECT_GT(fisheye_view.at("width_deg").get<double>(), 180.0);
  EXPECT_FALSE(fisheye.at("window.central_difference_gradients").get<bool>());
  EXPECT_EQ(fisheye.at("window.max_iterations").get<int>(), WindowOptions{}.max_iterations);
  EXPECT_EQ(fisheye_log.find("narrow view"), std::string::npos) << fisheye_log;
  const auto [crop_view, crop, crop_log] = run("crop", {"--camera-model", "pinhole-crop:90"});
  EXPECT_TRUE(crop_view.at("narrow").get<bool>());
  EXPECT_TRUE(crop_view.at("narrow_view_window").get<bool>());  // the render has exposure times
  EXPECT_TRUE(crop_view.at("narrow_view_tracking").get<bool>());
  EXPECT_EQ(crop.at("reference_depths.neighbours").get<int>(), 8);
  EXPECT_NE(crop_log.find("reference points whose inverse distance"), std::string::npos)
      << crop_log;
  // The 96-pixel crop's corner pixel centres, 47.5 px from the centre at f = 48.
  EXPECT_NEAR(crop_view.at("width_deg").get<double>(),
              2.0 * std::atan(std::sqrt(2.0) * 47.5 / 48.0) * 180.0 / M_PI, 0.05);
  EXPECT_TRUE(crop.at("window.central_difference_gradients").get<bool>());
  EXPECT_EQ(crop.at("window.max_iterations").get<int>(), 3);
  EXPECT_NE(crop_log.find("narrow view"), std::string::npos) << crop_log;
  const auto [set_view, set, set_log] =
      run("set", {"--camera-model", "pinhole-crop:90", "--set", "window.max_iterations=2"});
  EXPECT_EQ(set.at("window.max_iterations").get<int>(), 2);
  EXPECT_TRUE(set.at("window.central_difference_gradients").get<bool>());
  EXPECT_EQ(set_log.find("the window solves"), std::string::npos) << set_log;
  EXPECT_NE(set_log.find("reference points whose inverse distance"), std::string::npos)
      << set_log;
  const auto [all_view, all, all_log] = run(
      "all", {"--camera-model", "pinhole-crop:90", "--set", "reference_depths.neighbours=0"});
  EXPECT_EQ(all.at("reference_depths.neighbours").get<int>(), 0);
  EXPECT_EQ(all_log.find("reference points whose inverse distance"), std::string::npos)
      << all_log;
}

}  // namespace
}  // namespace omnidso::cli
