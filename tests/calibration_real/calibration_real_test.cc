// The `omnidso calibrate` executable on the real fisheye photos (calibrate_real_photos.hpp),
// KB4 only (a few seconds: the fast suite), against cv::fisheye::calibrate run here on the
// corners the command kept. Both minimise the same squared reprojection error over the same
// corners, so the command's RMS must not exceed OpenCV's by more than 2 % (it may be lower:
// a better minimum), and the focal lengths agree to 1 %; KB4 must also land within 1 % of the
// published focal length (558.5, 560.5) and 3 px of the principal point (620.5, 381.9).
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>

#include "calibrate_real_photos.hpp"

namespace omnidso::test {
namespace {

using Json = nlohmann::json;

// One test, so that ctest (one process per test) runs the executable once.
TEST(CalibrateRealPhotosKb4Test, MatchesOpenCvFisheyeAndThePublishedCalibration) {
  const std::unique_ptr<Json> calibration = calibrateRealPhotos("kb4");
  if (!calibration) GTEST_SKIP() << missingDataMessage("fisheye_calibration_jy");
  EXPECT_EQ(calibration->at("detections").size(), 34u);
  EXPECT_TRUE(calibration->at("images_without_board").empty());
  EXPECT_EQ(calibration->at("image_size"), Json::array({1280, 800}));
  EXPECT_GE(modelOf(*calibration, "kb4").at("num_views").get<int>(), 32);

  const BoardCorners in = keptCorners(*calibration);
  cv::Matx33d K;
  cv::Vec4d D;
  std::vector<cv::Vec3d> rvecs, tvecs;
  cv::fisheye::calibrate(in.object, in.image, kRealImageSize, K, D, rvecs, tvecs,
                         cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
                         cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 500,
                                          1e-12));
  std::vector<std::vector<cv::Point2d>> projected(in.object.size());
  for (size_t v = 0; v < in.object.size(); ++v)
    cv::fisheye::projectPoints(in.object[v], projected[v], rvecs[v], tvecs[v], K, D);
  const double opencv_rms = rmsOf(projected, in.image);
  const Json& kb4 = modelOf(*calibration, "kb4");
  const double our_rms = kb4.at("rms_px").get<double>();
  std::cout << "KB4 RMS: omnidso calibrate " << our_rms << " px, cv::fisheye " << opencv_rms
            << " px; fx " << parameter(kb4, "fx") << " vs " << K(0, 0) << "\n";
  EXPECT_LE(our_rms, 1.02 * opencv_rms);
  EXPECT_NEAR(parameter(kb4, "fx"), K(0, 0), 0.01 * K(0, 0));
  EXPECT_NEAR(parameter(kb4, "fy"), K(1, 1), 0.01 * K(1, 1));
  EXPECT_NEAR(parameter(kb4, "fx"), 558.5, 0.01 * 558.5);
  EXPECT_NEAR(parameter(kb4, "fy"), 560.5, 0.01 * 560.5);
  EXPECT_NEAR(parameter(kb4, "cx"), 620.5, 3.0);
  EXPECT_NEAR(parameter(kb4, "cy"), 381.9, 3.0);
}

}  // namespace
}  // namespace omnidso::test
