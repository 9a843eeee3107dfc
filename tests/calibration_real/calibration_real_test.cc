// Calibration of the real fisheye photos of ../shared/data/fisheye_calibration_jy/left
// (34 views, 8×6 inner corners, 1280×800) against OpenCV's own calibrators run here on the
// same detected corners: cv::fisheye::calibrate (KB4) and cv::omnidir::calibrate (Mei,
// = ucm-radtan). Both minimise the same squared reprojection error over the same corners,
// so our RMS must not exceed theirs by more than 2 % (it may be lower: a better minimum).
// RMS everywhere is √(mean ‖projection − detection‖²) over corners, computed here from the
// returned parameters (OpenCV's own return values use other normalisations).
#include <gtest/gtest.h>

#include <omnidso/cameras/calibration/calibration.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/ccalib/omnidir.hpp>

#include "test_data.hpp"

namespace omnidso {
namespace {

struct OpenCvInput {
  std::vector<std::vector<cv::Point3d>> object;
  std::vector<std::vector<cv::Point2d>> image;
  std::vector<size_t> view_index;  // into the detections
};

OpenCvInput openCvInput(const BoardDetections& d, const BoardSpec& board,
                        const CornerSelection& s) {
  OpenCvInput in;
  for (size_t v = 0; v < d.views.size(); ++v) {
    if (!s.view_used[v]) continue;
    in.object.emplace_back();
    in.image.emplace_back();
    for (int k = 0; k < board.numCorners(); ++k) {
      const Eigen::Vector3d X = board.corner(k);
      in.object.back().emplace_back(X.x(), X.y(), X.z());
      in.image.back().emplace_back(d.views[v].corners[k].x(), d.views[v].corners[k].y());
    }
    in.view_index.push_back(v);
  }
  return in;
}

double rmsOf(const std::vector<std::vector<cv::Point2d>>& projected,
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

// Our RMS over the views listed (the views OpenCV used).
double rmsOver(const ModelCalibration& m, const std::vector<size_t>& views) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t v : views)
    for (const Eigen::Vector2d& r : m.fit.residuals[v]) sum += r.squaredNorm(), ++n;
  return std::sqrt(sum / static_cast<double>(n));
}

const cv::TermCriteria kCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 500, 1e-12);

class CalibrationRealTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto dir = test::sharedDataDir("fisheye_calibration_jy");
    if (!dir) return;
    detections_ = new BoardDetections(detectBoardsInFolder((*dir / "left").string(), board_));
    report_ = new CalibrationReport(calibrateModels(*detections_, board_, {"kb4", "ucm-radtan"}));
  }
  static void TearDownTestSuite() {
    delete detections_;
    delete report_;
  }
  void SetUp() override {
    if (!detections_) GTEST_SKIP() << test::missingDataMessage("fisheye_calibration_jy");
  }
  static inline const BoardSpec board_{8, 6, 1.0};
  static inline BoardDetections* detections_ = nullptr;
  static inline CalibrationReport* report_ = nullptr;
};

TEST_F(CalibrationRealTest, DetectsTheBoardInEveryViewAndKeepsThem) {
  EXPECT_EQ(detections_->views.size(), 34u);
  EXPECT_TRUE(detections_->without_board.empty());
  EXPECT_EQ(detections_->width, 1280);
  EXPECT_EQ(detections_->height, 800);
  EXPECT_GE(report_->selection.numViews(), 32);
}

TEST_F(CalibrationRealTest, Kb4MatchesOpenCvFisheyeAndThePublishedCalibration) {
  const OpenCvInput in = openCvInput(*detections_, board_, report_->selection);
  cv::Matx33d K;
  cv::Vec4d D;
  std::vector<cv::Vec3d> rvecs, tvecs;
  cv::fisheye::calibrate(in.object, in.image, cv::Size(1280, 800), K, D, rvecs, tvecs,
                         cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
                         kCriteria);
  std::vector<std::vector<cv::Point2d>> projected(in.object.size());
  for (size_t v = 0; v < in.object.size(); ++v)
    cv::fisheye::projectPoints(in.object[v], projected[v], rvecs[v], tvecs[v], K, D);
  const double opencv_rms = rmsOf(projected, in.image);
  const ModelCalibration& kb4 = report_->models.at(0);
  const double our_rms = rmsOver(kb4, in.view_index);
  std::cout << "KB4 RMS: omnidso " << our_rms << " px, cv::fisheye " << opencv_rms << " px\n";
  EXPECT_LE(our_rms, 1.02 * opencv_rms);
  const Eigen::VectorXd p = kb4.fit.camera.params();
  EXPECT_NEAR(p[0], 558.5, 0.01 * 558.5);
  EXPECT_NEAR(p[1], 560.5, 0.01 * 560.5);
  EXPECT_NEAR(p[2], 620.5, 3.0);
  EXPECT_NEAR(p[3], 381.9, 3.0);
  EXPECT_NEAR(p[0], K(0, 0), 0.01 * K(0, 0));
}

TEST_F(CalibrationRealTest, UcmRadTanMatchesOpenCvOmnidir) {
  const OpenCvInput in = openCvInput(*detections_, board_, report_->selection);
  cv::Mat K, xi, D, idx;
  std::vector<cv::Mat> rvecs, tvecs;
  cv::omnidir::calibrate(in.object, in.image, cv::Size(1280, 800), K, xi, D, rvecs, tvecs,
                         cv::omnidir::CALIB_FIX_SKEW, kCriteria, idx);
  std::vector<std::vector<cv::Point2d>> projected, detected;
  std::vector<size_t> views;
  for (int i = 0; i < static_cast<int>(idx.total()); ++i) {
    const size_t v = static_cast<size_t>(idx.at<int>(i));
    projected.emplace_back();
    cv::omnidir::projectPoints(in.object[v], projected.back(), rvecs[static_cast<size_t>(i)],
                               tvecs[static_cast<size_t>(i)], K, xi.at<double>(0), D);
    detected.push_back(in.image[v]);
    views.push_back(in.view_index[v]);
  }
  const double opencv_rms = rmsOf(projected, detected);
  const double our_rms = rmsOver(report_->models.at(1), views);
  std::cout << "UCM+radtan RMS over " << views.size() << " views: omnidso " << our_rms
            << " px, cv::omnidir " << opencv_rms << " px\n";
  EXPECT_GE(views.size(), 20u);
  EXPECT_LE(our_rms, 1.02 * opencv_rms);
}

}  // namespace
}  // namespace omnidso
