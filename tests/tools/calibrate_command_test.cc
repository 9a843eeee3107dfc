// `omnidso calibrate` in-process on chessboard images rendered here through a known KB4
// camera (ray casting each pixel onto the board plane, 3 × 3 supersampled), and its bad
// input: each case one omnidso::Error (main() turns it into exit status 2) and no --out,
// and the same refusals through the executable (status 2, one line).
#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/core/error.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sys/wait.h>

namespace omnidso {
namespace {
namespace fs = std::filesystem;

constexpr int kWidth = 640, kHeight = 400;
constexpr double kSquare = 0.04;

Camera renderCamera() {
  Eigen::VectorXd p(8);
  p << 280.0, 281.0, 318.5, 201.0, -0.01, 0.004, -0.002, 0.0005;
  return Camera::create("kb4", p, kWidth, kHeight);
}

// A 9 × 7-square board (8 × 6 inner corners) with a one-square white margin, grey beyond.
cv::Mat renderBoard(const Camera& camera, const SE3d& T_camera_board) {
  const Eigen::Matrix3d R = T_camera_board.rotationMatrix();
  const Eigen::Vector3d n = R.col(2), t = T_camera_board.translation();
  cv::Mat image(kHeight, kWidth, CV_8U);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      double sum = 0.0;
      for (int s = 0; s < 9; ++s) {
        const Eigen::Vector2d uv(u + (s % 3 - 1) / 3.0, v + (s / 3 - 1) / 3.0);
        Eigen::Vector3d b;
        double grey = 128.0;
        if (camera.unproject(uv, b) && n.dot(b) != 0.0 && n.dot(t) / n.dot(b) > 0) {
          const Eigen::Vector3d X = R.transpose() * (n.dot(t) / n.dot(b) * b - t);
          const int i = static_cast<int>(std::floor(X.x() / kSquare)) + 1;
          const int j = static_cast<int>(std::floor(X.y() / kSquare)) + 1;
          if (i >= -1 && i <= 9 && j >= -1 && j <= 7) {
            const bool margin = i == -1 || i == 9 || j == -1 || j == 7;
            grey = margin || (i + j) % 2 ? 255.0 : 0.0;
          }
        }
        sum += grey;
      }
      image.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(std::lround(sum / 9));
    }
  }
  return image;
}

SE3d boardPose(int i) {
  const double az = 2 * M_PI * i / 7.0, el = (i == 0 ? 0.0 : 0.3);
  const Eigen::Vector3d dir(std::sin(el) * std::cos(az), std::sin(el) * std::sin(az),
                            std::cos(el));
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(el, Eigen::Vector3d(-dir.y(), dir.x(), 0).normalized()) *
       Eigen::AngleAxisd((i % 2 ? 0.35 : -0.35), Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Vector3d centre(3.5 * kSquare, 2.5 * kSquare, 0);
  return SE3d(R, Eigen::Vector3d(0.4 * dir - R * centre));
}

class CalibrateCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("omnidso_calibrate_" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
             "_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_ / "images");
  }
  void TearDown() override { fs::remove_all(root_); }

  void renderViews(int count) {
    for (int i = 0; i < count; ++i)
      cv::imwrite((root_ / "images" / ("view" + std::to_string(10 + i) + ".png")).string(),
                  renderBoard(renderCamera(), boardPose(i)));
  }
  void run(const std::string& arguments) {
    CLI::App app;
    app.require_subcommand(1);
    cli::registerCalibrateCommand(app);
    app.parse("calibrate " + arguments);
  }
  // The message of the omnidso::Error thrown; also checks that --out was not created.
  std::string failure(const std::string& arguments) {
    const fs::path out = root_ / "out";
    try {
      run(arguments + " --out " + out.string());
    } catch (const Error& e) {
      EXPECT_FALSE(fs::exists(out)) << arguments;
      for (const auto& entry : fs::directory_iterator(root_))
        EXPECT_EQ(entry.path().string().find(".partial-"), std::string::npos);
      return e.what();
    }
    ADD_FAILURE() << "no error for: " << arguments;
    return "";
  }
  fs::path images() const { return root_ / "images"; }
  fs::path root_;
};

TEST_F(CalibrateCommandTest, CalibratesRenderedViewsAndWritesEveryOutput) {
  renderViews(7);
  const fs::path out = root_ / "out";
  run(images().string() + " --board 8x6 --square 0.04 --models kb4,ucm,ds --out " +
      out.string() + " --json");
  for (const char* file : {"calibration.json", "comparison.md", "camchain.yaml", "coverage.png",
                           "view_rms.png", "residuals_kb4.png", "residuals_ds.png",
                           "models/kb4/camera.txt", "models/ucm/camera.txt",
                           "models/ds/camchain.yaml"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  EXPECT_FALSE(fs::exists(out / "models/ds/camera.txt"));  // camera.txt has no DS form
  std::ifstream json_file(out / "calibration.json");
  const nlohmann::json json = nlohmann::json::parse(json_file);
  EXPECT_EQ(json["models"].size(), 3u);
  EXPECT_GE(json["models"][0]["num_views"].get<int>(), 5);
  // The written files load back as the models reported. (Accuracy is checked on the real
  // photos against OpenCV and on exact synthetic corners; on these rendered views KB4's fx
  // comes out 4 % low — an open question about this renderer or the detector, see the
  // issue-17 report — so no accuracy is asserted here.)
  for (const nlohmann::json& model : json["models"]) {
    const std::string name = model["model"].get<std::string>();
    const Camera camera = loadCalibration((out / "models" / name / "camchain.yaml").string());
    EXPECT_EQ(camera.modelName(), name);
    const std::vector<std::string> names = camera.paramNames();
    for (size_t i = 0; i < names.size(); ++i)
      EXPECT_DOUBLE_EQ(camera.params()[static_cast<long>(i)],
                       model["parameters"][names[i]]["value"].get<double>())
          << name << " " << names[i];
  }
  EXPECT_EQ(loadCalibration((out / "camchain.yaml").string()).modelName(),
            json["selected"].get<std::string>());
  // A second run into the same folder needs --force.
  EXPECT_THROW(run(images().string() + " --board 8x6 --models kb4 --out " + out.string()),
               Error);
}

TEST_F(CalibrateCommandTest, RejectsBadInputWithOneClearMessage) {
  EXPECT_NE(failure((root_ / "missing").string() + " --board 8x6").find("no such folder"),
            std::string::npos);
  EXPECT_NE(failure(images().string() + " --board 8x6").find("no image files"),
            std::string::npos);
  EXPECT_NE(failure(images().string() + " --board 8by6").find("expected COLSxROWS"),
            std::string::npos);
  EXPECT_NE(failure(images().string() + " --board 1x6").find("at least 2x2"), std::string::npos);
  EXPECT_NE(failure(images().string() + " --board 8x6 --models ucm,fisheye62")
                .find("fisheye62"),
            std::string::npos);
  EXPECT_NE(failure(images().string() + " --board 8x6 --models ucm --select kb4")
                .find("not among --models"),
            std::string::npos);
  cv::imwrite((images() / "blank.png").string(), cv::Mat(kHeight, kWidth, CV_8U, cv::Scalar(90)));
  EXPECT_NE(failure(images().string() + " --board 8x6").find("no 8x6 chessboard found"),
            std::string::npos);
}

TEST_F(CalibrateCommandTest, RejectsUnreadableAndMixedSizeImages) {
  cv::imwrite((images() / "a.png").string(), cv::Mat(kHeight, kWidth, CV_8U, cv::Scalar(90)));
  std::ofstream(images() / "b.png") << "not a PNG";
  EXPECT_NE(failure(images().string() + " --board 8x6").find("b.png: cannot read the image"),
            std::string::npos);
  fs::remove(images() / "b.png");
  cv::imwrite((images() / "c.png").string(), cv::Mat(kHeight / 2, kWidth, CV_8U, cv::Scalar(90)));
  EXPECT_NE(failure(images().string() + " --board 8x6").find("c.png: image size 640x200 differs"),
            std::string::npos);
}

// The same refusals through the executable, as a user meets them: status 2, one line
// "omnidso: error: ..." naming the cause, and no --out.
TEST_F(CalibrateCommandTest, ExecutableExitsWithStatusTwoAndWritesNothing) {
  const fs::path out = root_ / "out", log = root_ / "log.txt";
  const auto refuse = [&](const std::string& arguments, const std::string& expected) {
    SCOPED_TRACE(arguments);
    const int status = std::system((std::string(OMNIDSO_EXECUTABLE) + " calibrate " + arguments +
                                    " --out " + out.string() + " > " + log.string() + " 2>&1")
                                       .c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2);
    std::ifstream file(log);
    const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text.rfind("omnidso: error: ", 0), 0u) << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
    EXPECT_NE(text.find(expected), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(out));
  };
  refuse((root_ / "missing").string() + " --board 8x6", "no such folder");
  refuse(images().string() + " --board 8x6", "no image files");
  refuse(images().string() + " --board 8by6", "expected COLSxROWS");
  refuse(images().string() + " --board 8x6 --models ucm,fisheye62", "fisheye62");
  std::ofstream(images() / "b.png") << "not a PNG";
  refuse(images().string() + " --board 8x6", "b.png: cannot read the image");
  fs::remove(images() / "b.png");
  cv::imwrite((images() / "blank.png").string(), cv::Mat(kHeight, kWidth, CV_8U, cv::Scalar(90)));
  refuse(images().string() + " --board 8x6", "no 8x6 chessboard found");
}

TEST_F(CalibrateCommandTest, RejectsFewerThanFourViews) {
  renderViews(3);
  EXPECT_NE(failure(images().string() + " --board 8x6").find("usable views show the board; at least 4"),
            std::string::npos);
}

}  // namespace
}  // namespace omnidso
