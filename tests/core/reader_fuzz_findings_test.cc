// Inputs on which libFuzzer (fuzz/, `make fuzz`) made a reader fail other than by
// omnidso::Error, kept after the fix: each must now be refused with one Error that names the
// file and the line (docs/architecture.md, "Sanitizers and fuzzing").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <omnidso/core/dataset.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/image_io.hpp>

#include "temp_dir.hpp"

namespace omnidso {
namespace {

namespace fs = std::filesystem;

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// The message of the Error that FN throws; fails the test when it throws anything else.
template <typename Fn>
std::string errorMessage(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no omnidso::Error";
  return "";
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

}  // namespace
}  // namespace omnidso
