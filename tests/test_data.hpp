#pragma once
// Where the real data of ../shared/data is: the OMNIDSO_DATA_DIR environment variable
// (ctest sets it from the CMake cache). Tests skip with a message when it is absent:
//   const auto dir = omnidso::test::sharedDataDir("fisheye_calibration_jy");
//   if (!dir) GTEST_SKIP() << omnidso::test::missingDataMessage("fisheye_calibration_jy");

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

namespace omnidso::test {

inline std::optional<std::filesystem::path> sharedDataDir(const std::string& sub) {
  const char* env = std::getenv("OMNIDSO_DATA_DIR");
  const std::filesystem::path root = env ? env : "../shared/data";
  const std::filesystem::path dir = root / sub;
  if (!std::filesystem::is_directory(dir)) return std::nullopt;
  return dir;
}

inline std::string missingDataMessage(const std::string& sub) {
  const char* env = std::getenv("OMNIDSO_DATA_DIR");
  return "real data '" + sub + "' not found under " + std::string(env ? env : "../shared/data") +
         " (set OMNIDSO_DATA_DIR); skipped";
}

}  // namespace omnidso::test
