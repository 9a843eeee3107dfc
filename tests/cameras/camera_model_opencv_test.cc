// The camera models against independent implementations in OpenCV: Mei's model (UCM +
// radtan) against cv::omnidir, KB4 against cv::fisheye, pinhole + radtan against
// cv::projectPoints. Both sides evaluate the same closed-form expressions in double, so they
// agree to rounding (~1e-12 px); 1e-6 px leaves room for a different order of operations.

#include "cameras/camera_model_test_utils.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/ccalib/omnidir.hpp>
#include <opencv2/core.hpp>

#include <vector>

namespace omnidso {
namespace {

constexpr int kNumPoints = 10000;
constexpr double kMaxPixelDifference = 1e-6;

cv::Mat cameraMatrix(double fx, double fy, double cx, double cy) {
  // Skew s = 0: the project's models have none.
  return (cv::Mat_<double>(3, 3) << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0);
}

std::vector<cv::Point3d> toCv(const std::vector<Eigen::Vector3d>& points) {
  std::vector<cv::Point3d> out;
  out.reserve(points.size());
  for (const auto& p : points) out.emplace_back(p.x(), p.y(), p.z());
  return out;
}

template <typename Model>
double maxDifference(const Model& camera, const std::vector<Eigen::Vector3d>& points,
                     const std::vector<cv::Point2d>& reference) {
  double worst = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    EXPECT_TRUE(camera.project(points[i], uv));
    worst = std::max(worst, (uv - Eigen::Vector2d(reference[i].x, reference[i].y)).norm());
  }
  return worst;
}

// Identity pose: rvec = tvec = 0.
cv::Mat zeroVector() { return cv::Mat::zeros(3, 1, CV_64F); }

// cv::omnidir: X/‖X‖, then (xs, ys)/(zs + ξ), then radtan (k1 k2 p1 p2), then K.
TEST(CameraModelOpenCv, UnifiedRadTanMatchesOmnidir) {
  const auto tc = test::realisticCameras<UnifiedRadTanCamera<double>>().front();
  const auto& p = tc.camera.params();
  const std::vector<Eigen::Vector3d> points = test::randomValidPoints(tc, kNumPoints, 23);
  const cv::Mat K = cameraMatrix(p[0], p[1], p[2], p[3]);
  const cv::Mat D = (cv::Mat_<double>(1, 4) << p[5], p[6], p[7], p[8]);
  std::vector<cv::Point2d> reference;
  cv::omnidir::projectPoints(toCv(points), reference, zeroVector(), zeroVector(), K, p[4], D);
  ASSERT_EQ(reference.size(), points.size());
  EXPECT_LT(maxDifference(tc.camera, points, reference), kMaxPixelDifference);
}

// cv::fisheye uses θ = atan(r/z) and so only handles points in front of the camera.
TEST(CameraModelOpenCv, KannalaBrandtMatchesFisheye) {
  const auto tc = test::realisticCameras<KannalaBrandtCamera<double>>().front();
  const auto& p = tc.camera.params();
  std::vector<Eigen::Vector3d> points;
  for (const auto& point : test::randomValidPoints(tc, 2 * kNumPoints, 29)) {
    if (point.z() > 1e-3 * point.norm() && static_cast<int>(points.size()) < kNumPoints) {
      points.push_back(point);
    }
  }
  ASSERT_EQ(static_cast<int>(points.size()), kNumPoints);
  const cv::Mat K = cameraMatrix(p[0], p[1], p[2], p[3]);
  const cv::Mat D = (cv::Mat_<double>(1, 4) << p[4], p[5], p[6], p[7]);
  std::vector<cv::Point2d> reference;
  cv::fisheye::projectPoints(toCv(points), reference, zeroVector(), zeroVector(), K, D);
  ASSERT_EQ(reference.size(), points.size());
  EXPECT_LT(maxDifference(tc.camera, points, reference), kMaxPixelDifference);
}

TEST(CameraModelOpenCv, PinholeRadTanMatchesProjectPoints) {
  const auto tc = test::realisticCameras<PinholeRadTanCamera<double>>().front();
  const auto& p = tc.camera.params();
  const std::vector<Eigen::Vector3d> points = test::randomValidPoints(tc, kNumPoints, 31);
  const cv::Mat K = cameraMatrix(p[0], p[1], p[2], p[3]);
  const cv::Mat D = (cv::Mat_<double>(1, 4) << p[4], p[5], p[6], p[7]);
  std::vector<cv::Point2d> reference;
  cv::projectPoints(toCv(points), zeroVector(), zeroVector(), K, D, reference);
  ASSERT_EQ(reference.size(), points.size());
  EXPECT_LT(maxDifference(tc.camera, points, reference), kMaxPixelDifference);
}

}  // namespace
}  // namespace omnidso
