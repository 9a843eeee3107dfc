#pragma once
// Every tunable of OdometryOptions under a dotted name ("window.max_iterations",
// "initializer.max_rmse", …), so that a researcher changes one without recompiling:
// `omnidso run --set NAME=VALUE` (repeatable) or `--config FILE` (a YAML map NAME: VALUE,
// nested maps allowed: `window: {max_iterations: 10}`). Unknown names and unparsable values
// are errors that name them. The effective values go into summary.json.

#include <nlohmann/json.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {

// Sets one option; throws omnidso::Error naming the setting on an unknown name or bad value.
void applyOdometrySetting(OdometryOptions& options, const std::string& name, const std::string& value);
// "NAME=VALUE" as given to --set.
void applyOdometrySettingAssignment(OdometryOptions& options, const std::string& assignment);
// A YAML file of settings (flat dotted names or nested maps).
void applyOdometryConfigFile(OdometryOptions& options, const std::string& path);
// Every setting's current value, by name.
nlohmann::json odometrySettingsJson(const OdometryOptions& options);
std::vector<std::string> odometrySettingNames();

}  // namespace omnidso::cli
