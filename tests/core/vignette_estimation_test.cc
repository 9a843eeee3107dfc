// The radial vignette from tracked points (core/vignette_estimation.hpp), on frames cut from
// one textured scene by known motions and multiplied by a known vignette and exposure.
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/core/vignette_estimation.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

namespace omnidso {
namespace {

constexpr int kSize = 320;
const Eigen::Vector2d kCentre(0.5 * (kSize - 1), 0.5 * (kSize - 1));

// A scene of texture at two scales, values in about [40, 210].
cv::Mat makeScene(std::mt19937* rng) {
  std::normal_distribution<float> normal(0.f, 1.f);
  cv::Mat fine(1400, 1400, CV_32F), coarse(1400, 1400, CV_32F);
  for (int v = 0; v < fine.rows; ++v)
    for (int u = 0; u < fine.cols; ++u) {
      fine.at<float>(v, u) = normal(*rng);
      coarse.at<float>(v, u) = normal(*rng);
    }
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), 1.5);
  cv::GaussianBlur(coarse, coarse, cv::Size(0, 0), 8.0);
  cv::normalize(fine, fine, -1, 1, cv::NORM_MINMAX);
  cv::normalize(coarse, coarse, -1, 1, cv::NORM_MINMAX);
  return 125.f + 45.f * fine + 40.f * coarse;
}

// V(ρ) with ρ the distance from the centre over the half-diagonal (the estimator's radius
// for a frame that is all content).
double trueVignette(double rho, double strength) {
  return 1.0 - strength * (0.6 * rho * rho + 0.4 * rho * rho * rho * rho);
}

// Frame k: the scene seen through a similarity (zoom by 1 % a frame, a slow turn, a drift),
// times the vignette and the frame's exposure, plus noise.
ImageF renderFrame(const cv::Mat& scene, int k, double strength, bool moving, std::mt19937* rng) {
  const double t = moving ? k : 0.0;
  const double scale = std::pow(1.01, t), angle = 0.4 * t;
  cv::Mat A = cv::getRotationMatrix2D(cv::Point2f(700.f, 700.f), angle, scale);
  A.at<double>(0, 2) += 2.5 * t - (700.0 - kCentre.x());
  A.at<double>(1, 2) += 1.5 * t - (700.0 - kCentre.y());
  cv::Mat frame;
  cv::warpAffine(scene, frame, A, cv::Size(kSize, kSize), cv::INTER_LINEAR);
  const double exposure = 1.0 + 0.15 * std::sin(0.7 * k);
  std::normal_distribution<double> noise(0.0, 0.5);
  const double half_diagonal = kCentre.norm();
  ImageF out(kSize, kSize);
  for (int v = 0; v < kSize; ++v)
    for (int u = 0; u < kSize; ++u) {
      const double rho = (Eigen::Vector2d(u, v) - kCentre).norm() / half_diagonal;
      out(u, v) = static_cast<float>(frame.at<float>(v, u) * trueVignette(rho, strength) *
                                     exposure + noise(*rng));
    }
  return out;
}

VignetteEstimate estimate(double strength, bool moving, int num_pairs) {
  std::mt19937 rng(7);
  const cv::Mat scene = makeScene(&rng);
  VignetteEstimator estimator(kSize, kSize, Mask(), kCentre, 255.0);
  for (int k = 0; k < num_pairs; ++k)
    estimator.addPair(renderFrame(scene, 2 * k, strength, moving, &rng),
                      renderFrame(scene, 2 * k + 1, strength, moving, &rng));
  return estimator.solve();
}

TEST(VignetteEstimation, RecoversARadialFallOff) {
  // V = 1 … 0.55 at the corners. The knots' linear interpolation of a smooth g errs by
  // ≈ g″ h² / 8 ≈ 0.002 (h = 1/12), the pull of the smoothness and ridge terms (1 % and
  // 0.01 % of the data's information) by about as much; the tolerance allows the tracks'
  // noise besides.
  const VignetteEstimate e = estimate(0.45, true, 30);
  ASSERT_TRUE(e.valid) << e.reason;
  EXPECT_NEAR(e.radius, kCentre.norm(), 1e-9);
  for (double rho : {0.25, 0.5, 0.7, 0.8})
    EXPECT_NEAR(e.at(rho), trueVignette(rho, 0.45), 0.01) << "rho " << rho;
  // Tracks keep 23 px from the border (the window, the high-pass and the patch), so none
  // reaches ρ = (159.5 − 23) √2 / 226 = 0.85: beyond, V is held, not extrapolated.
  EXPECT_EQ(e.at(0.95), e.at(1.0));
  EXPECT_GT(e.at(1.0), trueVignette(1.0, 0.45) + 0.05);
}

TEST(VignetteEstimation, FindsNoneWhereThereIsNone) {
  const VignetteEstimate e = estimate(0.0, true, 30);
  ASSERT_TRUE(e.valid) << e.reason;
  for (double rho : {0.25, 0.5, 0.75, 0.9}) EXPECT_NEAR(e.at(rho), 1.0, 0.01) << "rho " << rho;
}

// A camera standing still: every point keeps its radius, so nothing can be measured, and the
// estimator says so instead of fitting the tracks' noise.
TEST(VignetteEstimation, AStillCameraMeasuresNothing) {
  const VignetteEstimate e = estimate(0.45, false, 30);
  EXPECT_FALSE(e.valid);
  EXPECT_NE(e.reason.find("hardly moved"), std::string::npos) << e.reason;
  EXPECT_EQ(e.at(0.75), 1.0);
}

// A field that brightens outwards is no lens's vignette (max_outward_rise): the estimator
// measures it and refuses it. V = 1 + 0.45 (0.6 ρ² + 0.4 ρ⁴) reaches 1.18 at ρ = 0.7 and 1.29
// at the tracks' farthest reach (0.85), far past the 5 % tolerance.
TEST(VignetteEstimation, RefusesAFieldThatBrightensOutwards) {
  const VignetteEstimate e = estimate(-0.45, true, 30);
  EXPECT_FALSE(e.valid);
  EXPECT_NE(e.reason.find("brightens away from the centre"), std::string::npos) << e.reason;
  EXPECT_EQ(e.at(0.75), 1.0);
}

// A rise within the tolerance is kept, as the estimates measured on renders with a true
// vignette (a hump of up to 2 % near the centre): V = 1 + 0.045 (0.6 ρ² + 0.4 ρ⁴) is 1.02 at
// ρ = 0.7 and 1.03 at the tracks' farthest reach (0.85).
TEST(VignetteEstimation, KeepsARiseWithinTheTolerance) {
  const VignetteEstimate e = estimate(-0.045, true, 30);
  ASSERT_TRUE(e.valid) << e.reason;
  for (double rho : {0.5, 0.7})
    EXPECT_NEAR(e.at(rho) / e.at(0.0), trueVignette(rho, -0.045), 0.01) << "rho " << rho;
}

TEST(VignetteEstimation, TooFewTracksGiveNoEstimate) {
  const VignetteEstimate e = estimate(0.45, true, 1);  // one pair: a few hundred points
  EXPECT_FALSE(e.valid);
  EXPECT_NE(e.reason.find("needed"), std::string::npos) << e.reason;
  EXPECT_EQ(e.at(0.5), 1.0);
  const ImageF map = e.map(8, 8);
  EXPECT_EQ(map(0, 0), 1.f);
}

TEST(VignetteEstimation, MapIsRadialAndPeaksAtOne) {
  const VignetteEstimate e = estimate(0.45, true, 30);
  ASSERT_TRUE(e.valid) << e.reason;
  const ImageF map = e.map(kSize, kSize);
  float largest = 0.f;
  for (int v = 0; v < kSize; ++v)
    for (int u = 0; u < kSize; ++u) largest = std::max(largest, map(u, v));
  // Normalised by its largest knot, which a pixel meets to within a pixel's step of ρ.
  EXPECT_LE(largest, 1.f);
  EXPECT_GT(largest, 0.999f);
  // Symmetric about the centre: the four corners alike.
  EXPECT_FLOAT_EQ(map(0, 0), map(kSize - 1, kSize - 1));
  EXPECT_FLOAT_EQ(map(0, kSize - 1), map(kSize - 1, 0));
  EXPECT_LT(map(0, 0), map(kSize / 2, kSize / 2));
}

}  // namespace
}  // namespace omnidso
