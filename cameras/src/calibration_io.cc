// Calibration format detection and the one entry point loadCalibration (calibration_io.hpp).
#include <filesystem>

#include "calibration_yaml.hpp"
#include "omnidso/cameras/calibration_io.hpp"
#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

bool hasKey(const YAML::Node& root, const char* key) { return root.IsMap() && root[key]; }

}  // namespace

CalibrationFormat detectCalibrationFormat(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw fileError(path, "no such calibration file");
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".txt") return CalibrationFormat::kDsoCameraTxt;
  const bool yaml_ext = ext == ".yaml" || ext == ".yml";
  YAML::Node root;
  try {
    root = detail::readYamlFile(path);
  } catch (const Error&) {
    if (yaml_ext) throw;  // a malformed YAML file: report the YAML error
    return CalibrationFormat::kDsoCameraTxt;
  }
  if (hasKey(root, "T_BS") || hasKey(root, "distortion_coefficients")) {
    return CalibrationFormat::kEurocSensor;
  }
  if (hasKey(root, "cam0") || hasKey(root, "camera_model")) return CalibrationFormat::kKalibr;
  if (yaml_ext) {
    throw fileError(path,
                    "not a calibration: expected Kalibr ('cam0' or 'camera_model') or "
                    "EuRoC sensor.yaml ('T_BS') fields");
  }
  return CalibrationFormat::kDsoCameraTxt;
}

Camera loadCalibration(const std::string& path) {
  switch (detectCalibrationFormat(path)) {
    case CalibrationFormat::kKalibr:
      return loadKalibr(path);
    case CalibrationFormat::kEurocSensor:
      return loadEurocSensor(path).camera;
    case CalibrationFormat::kDsoCameraTxt:
      break;
  }
  return loadDsoCameraTxt(path);
}

}  // namespace omnidso
