// The `omnidso calibrate` executable on the real fisheye photos (calibrate_real_photos.hpp),
// UCM+radtan against cv::omnidir::calibrate (Mei's model, the same one) run here on the
// corners the command kept: the command's RMS must not exceed OpenCV's by more than 2 % (it
// may be lower). cv::omnidir takes seconds on these corners: label `slow`.
#include <gtest/gtest.h>

#include <opencv2/ccalib/omnidir.hpp>

#include "calibrate_real_photos.hpp"

namespace omnidso::test {
namespace {

using Json = nlohmann::json;

// cv::omnidir::calibrate drops views it cannot initialise (idx lists the ones it kept), so
// both RMS are taken over those views; ours from the command's per-view RMS (over the same
// kept corners), each weighted by its number of corners.
TEST(CalibrateRealPhotosOmnidirTest, UcmRadTanMatchesOpenCvOmnidir) {
  const std::unique_ptr<Json> calibration = calibrateRealPhotos("ucm-radtan");
  if (!calibration) GTEST_SKIP() << missingDataMessage("fisheye_calibration_jy");
  const BoardCorners in = keptCorners(*calibration);
  cv::Mat K, xi, D, idx;
  std::vector<cv::Mat> rvecs, tvecs;
  cv::omnidir::calibrate(in.object, in.image, kRealImageSize, K, xi, D, rvecs, tvecs,
                         cv::omnidir::CALIB_FIX_SKEW,
                         cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 500,
                                          1e-12),
                         idx);
  std::vector<double> our_view_rms;
  for (const Json& view : modelOf(*calibration, "ucm-radtan").at("per_view"))
    if (!view.at("rms_px").is_null()) our_view_rms.push_back(view.at("rms_px").get<double>());
  ASSERT_EQ(our_view_rms.size(), in.image.size());
  std::vector<std::vector<cv::Point2d>> projected, detected;
  double our_sum = 0.0;
  size_t corners = 0;
  for (int i = 0; i < static_cast<int>(idx.total()); ++i) {
    const size_t v = static_cast<size_t>(idx.at<int>(i));
    projected.emplace_back();
    cv::omnidir::projectPoints(in.object[v], projected.back(), rvecs[static_cast<size_t>(i)],
                               tvecs[static_cast<size_t>(i)], K, xi.at<double>(0), D);
    detected.push_back(in.image[v]);
    our_sum += our_view_rms[v] * our_view_rms[v] * static_cast<double>(in.image[v].size());
    corners += in.image[v].size();
  }
  const double opencv_rms = rmsOf(projected, detected);
  const double our_rms = std::sqrt(our_sum / static_cast<double>(corners));
  std::cout << "UCM+radtan RMS over " << detected.size() << " views: omnidso calibrate "
            << our_rms << " px, cv::omnidir " << opencv_rms << " px\n";
  EXPECT_GE(detected.size(), 20u);
  EXPECT_LE(our_rms, 1.02 * opencv_rms);
}

}  // namespace
}  // namespace omnidso::test
