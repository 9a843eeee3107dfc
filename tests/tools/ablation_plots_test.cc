// The PNG plots of `omnidso ablate` and the plot renderer under them.
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/cli/ablation_plots.hpp>
#include <omnidso/cli/line_plot.hpp>
#include <omnidso/core/sim3.hpp>
#include <opencv2/imgcodecs.hpp>

#include "synth_test_util.hpp"

namespace omnidso::cli {
namespace {

// A circle of radius 2 m in the x-z plane at height y = 1.5, 40 poses at 10 Hz.
Trajectory circle() {
  Trajectory t;
  for (int i = 0; i < 40; ++i) {
    const double a = 2 * M_PI * i / 40.0;
    t.push_back(
        {0.1 * i, SE3d(Eigen::Quaterniond::Identity(), {2 * std::cos(a), 1.5, 2 * std::sin(a)})});
  }
  return t;
}

int pixelsOfColour(const cv::Mat& image, const cv::Scalar& colour) {
  int count = 0;
  for (int r = 0; r < image.rows; ++r)
    for (int c = 0; c < image.cols; ++c) {
      const cv::Vec3b p = image.at<cv::Vec3b>(r, c);
      count += p[0] == colour[0] && p[1] == colour[1] && p[2] == colour[2];
    }
  return count;
}

TEST(AblationPlotsTest, TopViewIsThePlaneOfTheTwoLargestExtents) {
  EXPECT_EQ(topViewAxes(circle()), (std::pair<int, int>{0, 2}));
}

TEST(AblationPlotsTest, NiceTicksAreOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(niceTickStep(10.0, 5), 2.0);
  EXPECT_DOUBLE_EQ(niceTickStep(0.7, 6), 0.2);
  EXPECT_DOUBLE_EQ(niceTickStep(4.0, 8), 0.5);
  EXPECT_DOUBLE_EQ(niceTickStep(0.0, 8), 1.0);
}

TEST(AblationPlotsTest, WritesTrajectoryAndAtePlotsWithEveryMethodDrawn) {
  test::TempDir tmp("ablation_plots");
  DatasetPlots input;
  input.name = "circle";
  input.ground_truth = circle();
  // An estimate at half scale, rotated and shifted: Sim(3) alignment brings it back.
  Trajectory estimate;
  const Sim3d distortion(0.5, Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
                         Eigen::Vector3d(1, 0, 0));
  for (const StampedPose& p : input.ground_truth)
    estimate.push_back({p.timestamp, distortion * p.pose});
  estimate[20].pose = SE3d(estimate[20].pose.rotation(),
                           estimate[20].pose.translation() + Eigen::Vector3d(0.05, 0, 0));
  input.methods = {{"native Kf7", estimate}, {"pinhole-crop:90 Kf7: failed 2/2", std::nullopt}};

  const std::vector<std::string> paths = writeDatasetPlots(tmp.str() + "/plots", input);
  ASSERT_EQ(paths.size(), 2u);
  for (const std::string& path : paths) {
    const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << path;
    EXPECT_GT(image.cols, 600);
    EXPECT_GT(pixelsOfColour(image, seriesColour(0)), 100) << path << ": method curve missing";
  }
  const cv::Mat top = cv::imread(paths[0], cv::IMREAD_COLOR);
  EXPECT_GT(pixelsOfColour(top, cv::Scalar(0, 0, 0)), 500) << "ground truth missing";
}

}  // namespace
}  // namespace omnidso::cli
