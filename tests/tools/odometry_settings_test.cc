// Named odometry settings (`omnidso run --set`, `--config`): every name reaches its option,
// and unknown names or bad values are refused with the name in the message.
#include <gtest/gtest.h>

#include <fstream>
#include <omnidso/cli/odometry_settings.hpp>
#include <omnidso/core/error.hpp>
#include <string>

#include "core/temp_dir.hpp"
#include "support/error_message.hpp"

namespace omnidso::cli {
namespace {

using test::errorMessage;

TEST(OdometrySettings, AssignmentsReachTheirOptions) {
  OdometryOptions o;
  applyOdometrySettingAssignment(o, "window.max_iterations=11");
  applyOdometrySettingAssignment(o, "initializer.regularizer_weight=2.5e2");
  applyOdometrySettingAssignment(o, "keyframe_decision.global_weight=1.5");
  EXPECT_EQ(o.window.max_iterations, 11);
  EXPECT_DOUBLE_EQ(o.initializer.regularizer_weight, 250.0);
  EXPECT_DOUBLE_EQ(o.keyframe_decision.global_weight, 1.5);
}

// The one list setting, the tracker's iterations per pyramid level (finest first): written
// with commas, or in brackets as summary.json prints it; empty, partial or non-positive
// lists are refused.
TEST(OdometrySettings, AListSettingTakesCommasOrBracketsAndRefusesBadEntries) {
  OdometryOptions o;
  applyOdometrySettingAssignment(o, "tracker.max_iterations=3, 4,5");
  EXPECT_EQ(o.tracker.max_iterations, (std::vector<int>{3, 4, 5}));
  applyOdometrySetting(o, "tracker.max_iterations", "[7]");
  EXPECT_EQ(o.tracker.max_iterations, (std::vector<int>{7}));
  for (const char* bad : {"", "[]", "3,,4", "3,4,", "3;4", "[3,4", "3.5,4", "0,4", "-1"}) {
    EXPECT_THROW(applyOdometrySetting(o, "tracker.max_iterations", bad), Error) << bad;
  }
  const std::string range =
      errorMessage([&] { applyOdometrySetting(o, "tracker.max_iterations", "2,0"); });
  EXPECT_NE(range.find("at least 1"), std::string::npos) << range;
  // A value that does not parse leaves the option untouched.
  OdometryOptions fresh;
  EXPECT_THROW(applyOdometrySetting(fresh, "tracker.max_iterations", "x"), Error);
  EXPECT_EQ(fresh.tracker.max_iterations, OdometryOptions().tracker.max_iterations);
}

TEST(OdometrySettings, JsonListsEveryNameWithItsValue) {
  OdometryOptions o;
  o.epipolar.min_quality = 4.25;
  const nlohmann::json j = odometrySettingsJson(o);
  EXPECT_EQ(j.size(), odometrySettingNames().size());
  EXPECT_DOUBLE_EQ(j.at("epipolar.min_quality").get<double>(), 4.25);
  // Every listed name can be set back from its own printed value.
  OdometryOptions copy;
  for (const auto& [name, value] : j.items()) applyOdometrySetting(copy, name, value.dump());
  EXPECT_EQ(odometrySettingsJson(copy), j);
}

TEST(OdometrySettings, RejectsUnknownNamesAndBadValues) {
  OdometryOptions o;
  EXPECT_THROW(applyOdometrySettingAssignment(o, "window.max_iteration=3"), Error);
  EXPECT_THROW(applyOdometrySettingAssignment(o, "window.max_iterations=3.5"), Error);
  EXPECT_THROW(applyOdometrySettingAssignment(o, "window.max_iterations=lots"), Error);
  EXPECT_THROW(applyOdometrySettingAssignment(o, "no_equals_sign"), Error);
  EXPECT_THROW(applyOdometrySettingAssignment(o, "marginalization.num_protected_newest="), Error);
  const std::string unknown = errorMessage([&] { applyOdometrySetting(o, "tracker.huber", "9"); });
  EXPECT_NE(unknown.find("tracker.huber_threshold"), std::string::npos)
      << "the message lists the real names: " << unknown;
  EXPECT_EQ(o.window.max_iterations, OdometryOptions().window.max_iterations);
}

TEST(OdometrySettings, ConfigFileTakesNestedAndDottedNamesAndNamesTheLineOfAnError) {
  test::TempDir dir;
  const std::string good = dir.file("good.yaml");
  std::ofstream(good) << "window:\n  max_iterations: 9\ninitializer.max_rmse: 20\n";
  OdometryOptions o;
  applyOdometryConfigFile(o, good);
  EXPECT_EQ(o.window.max_iterations, 9);
  EXPECT_DOUBLE_EQ(o.initializer.max_rmse, 20.0);

  const std::string bad = dir.file("bad.yaml");
  std::ofstream(bad) << "window:\n  max_iterations: 9\n  outlier_energy: 3\n";
  const std::string message = errorMessage([&] { applyOdometryConfigFile(o, bad); });
  EXPECT_NE(message.find("bad.yaml:3"), std::string::npos) << message;
  EXPECT_NE(message.find("window.outlier_energy"), std::string::npos) << message;
  EXPECT_THROW(applyOdometryConfigFile(o, dir.file("missing.yaml")), Error);

  // A list setting as a YAML sequence, and a sequence where a single value belongs.
  const std::string list = dir.file("list.yaml");
  std::ofstream(list) << "tracker:\n  max_iterations: [4, 5, 6]\n";
  applyOdometryConfigFile(o, list);
  EXPECT_EQ(o.tracker.max_iterations, (std::vector<int>{4, 5, 6}));
  const std::string not_list = dir.file("not_list.yaml");
  std::ofstream(not_list) << "tracker:\n  huber_threshold: [4, 5]\n";
  const std::string scalar = errorMessage([&] { applyOdometryConfigFile(o, not_list); });
  EXPECT_NE(scalar.find("not_list.yaml:2"), std::string::npos) << scalar;
}

}  // namespace
}  // namespace omnidso::cli
