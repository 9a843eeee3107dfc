#pragma once
// `omnidso calibrate` run as a user runs it (the executable) on the real fisheye photos of
// ../shared/data/fisheye_calibration_jy/left (34 views, 8×6 inner corners, 1280×800), and
// what the tests need to run OpenCV's own calibrators on the corners it wrote to
// calibration.json (the views and corners it kept). RMS everywhere is
// √(mean ‖projection − detection‖²) over corners, computed for OpenCV from its returned
// parameters (its own return values use other normalisations).

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include "test_data.hpp"

namespace omnidso::test {

constexpr int kRealBoardCols = 8, kRealBoardRows = 6;
inline const cv::Size kRealImageSize(1280, 800);

// calibration.json of `omnidso calibrate <data>/fisheye_calibration_jy/left --board 8x6
// --models MODELS`; null when the data are absent. Throws when the command fails.
inline std::unique_ptr<nlohmann::json> calibrateRealPhotos(const std::string& models) {
  const auto dir = sharedDataDir("fisheye_calibration_jy");
  if (!dir) return nullptr;
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() /
                      ("omnidso_calibrate_real_" + models + "_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string command = std::string("'") + OMNIDSO_EXECUTABLE + "' calibrate '" +
                              (*dir / "left").string() + "' --board 8x6 --models " + models +
                              " --out '" + out.string() + "' > /dev/null";
  const int status = std::system(command.c_str());
  std::ifstream file(out / "calibration.json");
  if (status != 0 || !file) throw std::runtime_error(command + ": status " + std::to_string(status));
  auto calibration = std::make_unique<nlohmann::json>(nlohmann::json::parse(file));
  fs::remove_all(out);
  return calibration;
}

// The kept corners of the kept views with their board points (unit squares: --square 1).
struct BoardCorners {
  std::vector<std::vector<cv::Point3d>> object;
  std::vector<std::vector<cv::Point2d>> image;
};

inline BoardCorners keptCorners(const nlohmann::json& calibration) {
  BoardCorners c;
  for (const nlohmann::json& view : calibration.at("detections")) {
    if (!view.at("used").get<bool>()) continue;
    c.object.emplace_back();
    c.image.emplace_back();
    for (int k = 0; k < kRealBoardCols * kRealBoardRows; ++k) {
      if (!view.at("corner_used").at(k).get<bool>()) continue;
      c.object.back().emplace_back(k % kRealBoardCols, k / kRealBoardCols, 0.0);
      const nlohmann::json& uv = view.at("corners").at(k);
      c.image.back().emplace_back(uv.at(0).get<double>(), uv.at(1).get<double>());
    }
  }
  return c;
}

inline double rmsOf(const std::vector<std::vector<cv::Point2d>>& projected,
                    const std::vector<std::vector<cv::Point2d>>& detected) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t v = 0; v < projected.size(); ++v)
    for (size_t k = 0; k < projected[v].size(); ++k, ++n) {
      const cv::Point2d e = projected[v][k] - detected[v][k];
      sum += e.dot(e);
    }
  return std::sqrt(sum / static_cast<double>(n));
}

inline const nlohmann::json& modelOf(const nlohmann::json& calibration, const std::string& name) {
  for (const nlohmann::json& m : calibration.at("models"))
    if (m.at("model") == name) return m;
  throw std::runtime_error("no model " + name + " in calibration.json");
}

inline double parameter(const nlohmann::json& model, const std::string& name) {
  return model.at("parameters").at(name).at("value").get<double>();
}

}  // namespace omnidso::test
