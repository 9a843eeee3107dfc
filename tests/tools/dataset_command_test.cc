// `omnidso synth` and `omnidso dataset info`, run in-process as the executable runs them.
#include <CLI/CLI.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <omnidso/cli/commands.hpp>
#include <omnidso/core/error.hpp>

#include "synth_test_util.hpp"
#include "test_data.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;

// Parses `command_line` with the synth and dataset commands registered; returns stdout.
// omnidso::Error propagates as it does to main().
std::string runCommand(const std::string& command_line) {
  CLI::App app;
  app.require_subcommand(1);
  cli::registerSynthCommand(app);
  cli::registerDatasetCommand(app);
  std::ostringstream captured;
  std::streambuf* const original = std::cout.rdbuf(captured.rdbuf());
  try {
    app.parse(command_line);
  } catch (...) {
    std::cout.rdbuf(original);
    throw;
  }
  std::cout.rdbuf(original);
  return captured.str();
}

std::string errorOf(const std::string& command_line) {
  try {
    runCommand(command_line);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(DatasetCommandTest, SynthWritesADatasetThatInfoReadsBack) {
  test::TempDir tmp("cli_synth");
  const std::string out = (tmp.path() / "seq").string();
  runCommand("synth --preset room185 --frames 3 --size 64x48 --seed 3 --quiet --out " + out);
  const nlohmann::json info = nlohmann::json::parse(runCommand("dataset info --json " + out));
  EXPECT_EQ(info["layout"], "tum");
  EXPECT_EQ(info["frames"], 3);
  EXPECT_EQ(info["width"], 64);
  EXPECT_EQ(info["height"], 48);
  EXPECT_EQ(info["camera"]["model"], "ucm");
  EXPECT_GT(info["camera"]["fov_deg"]["maximum"].get<double>(), 180.0);
  EXPECT_TRUE(info["photometric_calibration"]["present"].get<bool>());
  EXPECT_TRUE(info["ground_truth"]["present"].get<bool>());
  EXPECT_EQ(info["ground_truth"]["poses"], 3);
  // 3 frames at 20 Hz: 0.1 s; the rate is exact up to double rounding.
  EXPECT_NEAR(info["rate_hz"].get<double>(), 20.0, 1e-9);
  EXPECT_NEAR(info["time_span_s"].get<double>(), 0.1, 1e-12);

  // Same command, same bytes (a second directory).
  const std::string again = (tmp.path() / "again").string();
  runCommand("synth --preset room185 --frames 3 --size 64x48 --seed 3 --quiet --out " + again);
  for (const char* file : {"images/00000.png", "images/00002.png", "times.txt",
                           "groundtruth.txt", "camchain.yaml", "vignette.png"}) {
    std::ifstream a(fs::path(out) / file, std::ios::binary);
    std::ifstream b(fs::path(again) / file, std::ios::binary);
    const std::string bytes_a((std::istreambuf_iterator<char>(a)), {});
    const std::string bytes_b((std::istreambuf_iterator<char>(b)), {});
    EXPECT_FALSE(bytes_a.empty()) << file;
    EXPECT_EQ(bytes_a, bytes_b) << file;
  }
  // A non-empty output directory is refused without --force.
  EXPECT_NE(errorOf("synth --frames 1 --size 32x32 --quiet --out " + out).find("not empty"),
            std::string::npos);
}

TEST(DatasetCommandTest, SynthPinholeAblationDefaultsToNinetyDegrees) {
  test::TempDir tmp("cli_pinhole");
  const std::string out = (tmp.path() / "seq").string();
  runCommand("synth --camera-model pinhole --frames 1 --size 64x64 --quiet --out " + out);
  const nlohmann::json info = nlohmann::json::parse(runCommand("dataset info --json " + out));
  EXPECT_EQ(info["camera"]["model"], "pinhole");
  EXPECT_NEAR(info["camera"]["fov_deg"]["horizontal"].get<double>(), 90.0, 1e-6);
}

TEST(DatasetCommandTest, SynthRejectsABadSize) {
  EXPECT_NE(errorOf("synth --size 64by64 --out /nonexistent").find("--size"), std::string::npos);
}

// A copy of the static EuRoC clip built from links to its images, so that one image can be
// missing or replaced without copying 34 MB. restore() undoes a breakage.
class BrokenEurocCopy {
 public:
  BrokenEurocCopy(const fs::path& clip, const fs::path& dir)
      : clip_cam_(fs::absolute(clip) / "mav0" / "cam0"), cam_(dir / "mav0" / "cam0") {
    fs::create_directories(cam_ / "data");
    for (const auto& entry : fs::directory_iterator(clip_cam_ / "data")) {
      fs::create_symlink(entry.path(), cam_ / "data" / entry.path().filename());
    }
    restore();
  }
  void restore(const std::string& frame = "") const {
    fs::copy_file(clip_cam_ / "data.csv", cam_ / "data.csv", fs::copy_options::overwrite_existing);
    fs::copy_file(clip_cam_ / "sensor.yaml", cam_ / "sensor.yaml",
                  fs::copy_options::overwrite_existing);
    if (!frame.empty()) {
      fs::remove(cam_ / "data" / frame);
      fs::create_symlink(clip_cam_ / "data" / frame, cam_ / "data" / frame);
    }
  }
  const fs::path& cam() const { return cam_; }
  std::string str() const { return cam_.parent_path().parent_path().string(); }

 private:
  fs::path clip_cam_;
  fs::path cam_;
};

TEST(DatasetCommandTest, InfoReadsTheStaticEurocClip) {
  const auto clip = test::sharedDataDir("euroc_v101_static_clip");
  if (!clip) GTEST_SKIP() << test::missingDataMessage("euroc_v101_static_clip");
  const nlohmann::json info =
      nlohmann::json::parse(runCommand("dataset info --json " + clip->string()));
  EXPECT_EQ(info["layout"], "asl");
  EXPECT_EQ(info["frames"], 95);
  EXPECT_EQ(info["width"], 752);
  EXPECT_EQ(info["height"], 480);
  EXPECT_EQ(info["camera"]["model"], "pinhole-radtan");
  EXPECT_FALSE(info["exposure"]["known"].get<bool>());
  EXPECT_FALSE(info["ground_truth"]["present"].get<bool>());
}

TEST(DatasetCommandTest, InfoRejectsBrokenCopiesOfTheEurocClip) {
  const auto clip = test::sharedDataDir("euroc_v101_static_clip");
  if (!clip) GTEST_SKIP() << test::missingDataMessage("euroc_v101_static_clip");
  test::TempDir tmp("cli_broken");
  const BrokenEurocCopy copy(*clip, tmp.path());
  const std::string frame = "1403715274262142976.png";  // line 22 of data.csv
  const fs::path image = copy.cam() / "data" / frame;
  EXPECT_EQ(errorOf("dataset info " + copy.str()), "");  // the intact copy

  fs::remove(image);  // an image missing
  EXPECT_NE(errorOf("dataset info " + copy.str()).find("data.csv:22: image"), std::string::npos);

  fs::copy_file(*clip / "mav0" / "cam0" / "data" / frame, image);  // an image truncated
  fs::resize_file(image, 1000);
  std::string error = errorOf("dataset info " + copy.str());
  EXPECT_NE(error.find("data.csv:22:"), std::string::npos) << error;
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;

  fs::remove(image);  // an image of another size
  cv::imwrite(image.string(), cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)));
  error = errorOf("dataset info " + copy.str());
  EXPECT_NE(error.find("data.csv:22:"), std::string::npos) << error;
  EXPECT_NE(error.find("is 10x10, but the first image is 752x480"), std::string::npos) << error;
  copy.restore(frame);

  {  // timestamps out of order: lines 8 and 9 swapped
    std::ifstream in(copy.cam() / "data.csv");
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    std::swap(lines[7], lines[8]);
    std::ofstream out(copy.cam() / "data.csv");
    for (const std::string& line : lines) out << line << "\n";
  }
  EXPECT_NE(errorOf("dataset info " + copy.str()).find("data.csv:9: timestamp"),
            std::string::npos);
  copy.restore();

  {  // an unknown camera model
    std::ifstream in(copy.cam() / "sensor.yaml");
    std::string yaml((std::istreambuf_iterator<char>(in)), {});
    yaml.replace(yaml.find("camera_model: pinhole"), 21, "camera_model: fancy");
    std::ofstream(copy.cam() / "sensor.yaml") << yaml;
  }
  error = errorOf("dataset info " + copy.str());
  EXPECT_NE(error.find("sensor.yaml"), std::string::npos) << error;
  EXPECT_NE(error.find("fancy"), std::string::npos) << error;
  copy.restore();

  std::ofstream(copy.cam() / "data.csv") << "#timestamp [ns],filename\n";  // an empty index
  EXPECT_NE(errorOf("dataset info " + copy.str()).find("data.csv: empty"), std::string::npos);
}

}  // namespace
}  // namespace omnidso
