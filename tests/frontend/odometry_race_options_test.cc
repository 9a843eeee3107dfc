// The initialisation race's settings (odometry.hpp, InitializationRaceOptions) are checked when
// the odometry is made, before any frame: a bad one is an error that names it. Its behaviour is
// checked end to end (OdometryEndToEnd.InitialisationRaceRunsAsTheStartItKeeps).
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <omnidso/core/error.hpp>
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
           [](OdometryOptions& o) { o.race.max_frames = 0; }}) {
    const std::string message = errorOf(bad);
    EXPECT_NE(message.find("race.keyframes must lie in 2"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace omnidso
