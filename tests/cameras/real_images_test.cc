// The real fisheye images of ../shared/data/fisheye_calibration_jy with the calibration
// published for the left camera (the data's README): UCM + radial–tangential, 1280×800.
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/cameras/field_of_view.hpp>
#include <omnidso/cameras/rectification.hpp>
#include <omnidso/core/image_io.hpp>

#include "test_data.hpp"

namespace omnidso {
namespace {

Camera publishedLeftCamera() {
  Eigen::VectorXd p(9);
  p << 408.911, 410.488, 630.280, 431.917, 1.05343, -0.0082879, 0.0117789, 0.0228246, -0.0041849;
  return Camera::create("ucm-radtan", p, 1280, 800);
}

TEST(RealImagesTest, FisheyeImagesLoadAtTheCalibratedSize) {
  const auto dir = test::sharedDataDir("fisheye_calibration_jy");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("fisheye_calibration_jy");
  const ImageU8 image = readImageU8((*dir / "left" / "stereo_pair_000.jpg").string());
  EXPECT_EQ(image.width(), 1280);
  EXPECT_EQ(image.height(), 800);
  // A ξ > 1 fisheye on a 1280×800 sensor: the horizontal view exceeds 180°.
  EXPECT_GT(horizontalFovDeg(publishedLeftCamera()), 180.0);
}

// The paper's "DSO with pinhole model" input: a pinhole crop rectified from the fisheye.
TEST(RealImagesTest, RectifiedPinholeCropIsMostlyValid) {
  const auto dir = test::sharedDataDir("fisheye_calibration_jy");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("fisheye_calibration_jy");
  const ImageU8 image = readImageU8((*dir / "left" / "stereo_pair_000.jpg").string());
  const Camera crop = pinholeForFov(90.0, 640, 480);
  const RectificationMap map = makeRectificationMap(publishedLeftCamera(), crop);
  const ImageU8 rectified = remap(image, map);
  EXPECT_EQ(rectified.width(), 640);
  EXPECT_EQ(rectified.height(), 480);
  const Mask mask = validMask(map);
  const auto valid =
      std::count_if(mask.data(), mask.data() + mask.size(), [](std::uint8_t m) { return m != 0; });
  // A 90° × 74° view around the axis of a > 180° fisheye lies entirely inside the image.
  EXPECT_GT(static_cast<double>(valid) / mask.size(), 0.99);
  // The view shows the scene (a chessboard), not a constant fill: grey levels spread.
  double sum = 0.0;
  double sum_sq = 0.0;
  for (size_t i = 0; i < rectified.size(); ++i) {
    sum += rectified.data()[i];
    sum_sq += static_cast<double>(rectified.data()[i]) * rectified.data()[i];
  }
  const double mean = sum / rectified.size();
  EXPECT_GT(std::sqrt(sum_sq / rectified.size() - mean * mean), 10.0);
}

}  // namespace
}  // namespace omnidso
