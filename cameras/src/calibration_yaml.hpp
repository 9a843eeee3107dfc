#pragma once
// Internal to the calibration readers: a YAML file as a node, with OpenCV's `%YAML:1.0`
// first line (EuRoC's sensor.yaml) skipped since yaml-cpp rejects it. Throws omnidso::Error
// "FILE:LINE: malformed YAML: ..." for a syntax error and "FILE: cannot open" when unreadable.

#include <yaml-cpp/yaml.h>

#include <string>

namespace omnidso::detail {

YAML::Node readYamlFile(const std::string& path);

}  // namespace omnidso::detail
