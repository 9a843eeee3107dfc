// Inputs on which a reader's fuzz target (fuzz/, `make fuzz`) failed other than by
// omnidso::Error — an escaping exception, or undefined behaviour under UBSan — kept after the
// fix: each must now be refused with one Error that names the file and the line or field
// (docs/architecture.md, "Sanitizers and fuzzing"). Under `make test-asan` they also check
// that the refusal itself is free of undefined behaviour.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/cli/odometry_settings.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/image_io.hpp>

#include "core/temp_dir.hpp"
#include "support/error_message.hpp"

namespace omnidso {
namespace {

namespace fs = std::filesystem;
using test::errorMessage;

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// libFuzzer's crash-e072ad37: a 19-digit timestamp beyond int64 made std::stoll throw
// std::out_of_range, which no caller expects.
TEST(ReaderFuzzFindings, AslTimestampBeyondInt64IsRefusedNamingTheLine) {
  test::TempDir tmp;
  const fs::path cam = fs::path(tmp.file("asl")) / "mav0" / "cam0";
  fs::create_directories(cam / "data");
  writeImage((cam / "data" / "0.png").string(), ImageU8(4, 3, 128));
  writeText(cam / "data.csv",
            "#timestamp [ns],filename\n0,0.png\n9403636579763555584,0.png\n");
  const std::string message = errorMessage([&] { openDataset(tmp.file("asl")); });
  EXPECT_NE(message.find("data.csv:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("9403636579763555584"), std::string::npos) << message;
}

// libFuzzer's crash-32f342c8: T_BS a scalar instead of a mapping; yaml-cpp threw BadSubscript.
TEST(ReaderFuzzFindings, EurocSensorWhoseTransformIsNotAMappingIsRefused) {
  test::TempDir tmp;
  writeText(tmp.file("sensor.yaml"),
            "%YAML:1.0\nT_BS:\n  c%YAML:1.0\nresolution: [752, 480]\ncamera_model: pinhole\n"
            "intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
            "distortion_model: radial-tangential\n"
            "distortion_coefficients: [-0.28, 0.07, 0.0002, 1.7e-05]\n");
  const std::string message = errorMessage([&] { loadEurocSensor(tmp.file("sensor.yaml")); });
  EXPECT_NE(message.find("sensor.yaml: field 'T_BS'"), std::string::npos) << message;
}

// A width of 1e300 or 3e9 converted to int: undefined behaviour (UBSan's float-cast-overflow).
TEST(ReaderFuzzFindings, KalibrResolutionBeyondIntIsRefused) {
  test::TempDir tmp;
  for (const char* width : {"1e300", "3000000000", "100001"}) {
    writeText(tmp.file("camchain.yaml"),
              std::string("camera_model: pinhole\nintrinsics: [300, 300, 240, 240]\n"
                          "distortion_model: none\nresolution: [") +
                  width + ", 480]\n");
    const std::string message = errorMessage([&] { loadKalibr(tmp.file("camchain.yaml")); });
    EXPECT_NE(message.find("field 'resolution'"), std::string::npos) << width << ": " << message;
  }
}

TEST(ReaderFuzzFindings, DsoCameraTxtImageSizeBeyondIntIsRefused) {
  test::TempDir tmp;
  writeText(tmp.file("camera.txt"), "Pinhole 300 300 239 239 0\n1e300 480\n");
  const std::string message = errorMessage([&] { loadDsoCameraTxt(tmp.file("camera.txt")); });
  EXPECT_NE(message.find("camera.txt:2:"), std::string::npos) << message;
}

// A list or map as a setting's name: yaml-cpp's as<std::string>() threw BadConversion.
TEST(ReaderFuzzFindings, ConfigWhoseSettingNameIsNotTextIsRefusedNamingTheLine) {
  test::TempDir tmp;
  for (const char* text : {"[1, 2]: 3\n", "window:\n  ? [a, b]\n  : 1\n", "~: 1\n"}) {
    writeText(tmp.file("config.yaml"), text);
    OdometryOptions options;
    const std::string message =
        errorMessage([&] { cli::applyOdometryConfigFile(options, tmp.file("config.yaml")); });
    EXPECT_NE(message.find("config.yaml:"), std::string::npos) << text << message;
    EXPECT_NE(message.find("plain word"), std::string::npos) << text << message;
  }
}

}  // namespace
}  // namespace omnidso
