// Calibration format detection and the one entry point loadCalibration (calibration_io.hpp).
#include <filesystem>
#include <fstream>

#include "calibration_kitti.hpp"
#include "calibration_yaml.hpp"
#include "omnidso/cameras/calibration_io.hpp"
#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

bool hasKey(const YAML::Node& root, const char* key) { return root.IsMap() && root[key]; }

// KITTI's calib.txt: a line `P0: ...` anywhere (P0..P3 and Tr, in any order).
bool hasKittiP0Line(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open calibration file");
  for (std::string line; std::getline(in, line);) {
    if (detail::isKittiP0Line(line)) return true;
  }
  return false;
}

}  // namespace

CalibrationFormat detectCalibrationFormat(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw fileError(path, "no such calibration file");
  const std::string ext = std::filesystem::path(path).extension().string();
  const bool yaml_ext = ext == ".yaml" || ext == ".yml";
  if (!yaml_ext && hasKittiP0Line(path)) return CalibrationFormat::kKittiCalib;
  if (ext == ".txt") return CalibrationFormat::kDsoCameraTxt;
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
    case CalibrationFormat::kKittiCalib:
      throw fileError(path,
                      "KITTI's calib.txt has no image size: it is read with its dataset "
                      "(omnidso run / dataset info on the sequence directory, datasetCamera), "
                      "which takes the size from image_0/");
    case CalibrationFormat::kDsoCameraTxt:
      break;
  }
  return loadDsoCameraTxt(path);
}

}  // namespace omnidso
