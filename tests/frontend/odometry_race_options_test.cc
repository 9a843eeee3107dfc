// The initialisation race's settings (odometry.hpp, InitializationRaceOptions) are checked when
// the odometry is made, before any frame: a bad one is an error that names it. Its behaviour is
// checked end to end (OdometryEndToEnd.InitialisationRaceRunsAsTheStartItKeeps); the rival's
// options (raceRivalOptions) here.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/initializer.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

namespace omnidso {
namespace {

std::string errorOf(const std::function<void(OdometryOptions&)>& change) {
  OdometryOptions options;
  change(options);
  try {
    Odometry odometry(synth::syntheticCamera("pinhole", 90.0, 64, 64), options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(InitializationRaceOptions, BadSettingsAreRefusedByName) {
  EXPECT_EQ(errorOf([](OdometryOptions&) {}), "");
  EXPECT_EQ(errorOf([](OdometryOptions& o) { o.race.rival_snap_parallax_deg = 0.0; }), "");
  // Two keyframes: the initial pair's own window, the earliest the costs can be compared.
  EXPECT_EQ(errorOf([](OdometryOptions& o) { o.race.keyframes = 2; }), "");
  for (const auto& bad : std::vector<std::function<void(OdometryOptions&)>>{
           [](OdometryOptions& o) { o.race.keyframes = 1; },
           [](OdometryOptions& o) { o.race.keyframes = o.window.max_keyframes + 1; },
           [](OdometryOptions& o) { o.race.switch_gain = 0.0; },
           [](OdometryOptions& o) { o.race.rival_snap_translation_start_gain = 0.0; },
           [](OdometryOptions& o) { o.race.max_frames = 0; },
           [](OdometryOptions& o) { o.race.same_start_deg = std::nan(""); }}) {
    const std::string message = errorOf(bad);
    EXPECT_NE(message.find("race.keyframes must lie in 2"), std::string::npos) << message;
  }
}

// The rival differs from the configured start in its snap angle and in the start it adopts at
// the snap: the lowest error of the pre-snap path's solution and the pure translations', where
// the configured start asks a translation start for 0.95× (docs/performance.md, "A start inside
// a fast turn": under motion blur the right basin's error was 0.98–0.99× the wrong one's, and
// the rival kept the wrong one too). Everything else is the configured start's.
TEST(InitializationRaceOptions, TheRivalSnapsEarlierAndAdoptsTheLowestStart) {
  OdometryOptions options;
  options.initializer.max_rmse = 12.5;  // any setting: the rival copies it
  const OdometryOptions rival = raceRivalOptions(options);
  EXPECT_EQ(rival.initializer.snap_parallax_deg, options.race.rival_snap_parallax_deg);
  EXPECT_LT(rival.initializer.snap_parallax_deg, snapParallaxDeg(options.initializer));
  EXPECT_EQ(rival.initializer.snap_translation_start_gain, 1.0);
  EXPECT_EQ(options.initializer.snap_translation_start_gain, 0.95);
  EXPECT_EQ(rival.initializer.max_rmse, 12.5);
  EXPECT_EQ(rival.initializer.min_parallax_deg, options.initializer.min_parallax_deg);
  options.race.rival_snap_translation_start_gain = 0.8;  // the session-43 rival
  EXPECT_EQ(raceRivalOptions(options).initializer.snap_translation_start_gain, 0.8);
}

}  // namespace
}  // namespace omnidso
