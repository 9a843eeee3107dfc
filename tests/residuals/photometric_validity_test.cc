// Invalid projections: behind the camera (pinhole), outside the image, beyond UCM's fold,
// negative inverse distance, host pixels outside the model's image. The status says why,
// both cost functions return false, and nothing written is NaN or Inf.

#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "residuals/residual_test_support.hpp"

namespace omnidso::test {
namespace {

constexpr int kN = 8;

template <typename Tag>
struct InvalidCase {
  ImageF target = smoothTexture(kTestWidth, kTestHeight);
  PhotometricObservation<kN> obs;
  PhotometricBlocks<Tag::kNumParams> blocks;

  InvalidCase(const Eigen::Vector2d& host_pixel, const SE3d& T_host_target, double d) {
    obs.target_image = &target;
    obs.host.pixel = host_pixel;
    obs.host.intensity.fill(100.0);
    obs.host.sqrt_weight.fill(1.0);
    const SE3d host = poseFrom(0.1, -0.2, 0.3, 0.5, -0.2, 0.1);
    blocks.host_pose = poseBlock(host);
    blocks.target_pose = poseBlock(host * T_host_target);
    blocks.inverse_distance = d;
    blocks.intrinsics = Tag::params();
  }
};

// Both cost functions refuse to evaluate and leave no non-finite number behind.
template <typename Tag, typename Case>
void expectRejected(const Case& c, PhotometricStatus expected) {
  const auto pointers = c.blocks.pointers();
  EXPECT_EQ(Tag::status(c.obs, pointers.data()), expected);
  for (DifferentiationMode mode :
       {DifferentiationMode::kAnalytic, DifferentiationMode::kAutodiff}) {
    const std::unique_ptr<ceres::CostFunction> cost(Tag::photometric(mode, c.obs));
    std::array<double, kN> residuals;
    residuals.fill(0.0);
    std::array<double, kN * 7> j_host{}, j_target{};
    std::array<double, kN> j_d{};
    std::array<double, kN * 2> j_ah{}, j_at{};
    std::array<double, kN * Tag::kNumParams> j_c{};
    std::array<double*, 6> jacobians = {j_host.data(), j_target.data(), j_d.data(),
                                        j_ah.data(),   j_at.data(),     j_c.data()};
    EXPECT_FALSE(cost->Evaluate(pointers.data(), residuals.data(), nullptr));
    EXPECT_FALSE(cost->Evaluate(pointers.data(), residuals.data(), jacobians.data()));
    for (double r : residuals) EXPECT_TRUE(std::isfinite(r));
    for (double j : j_host) EXPECT_TRUE(std::isfinite(j));
    for (double j : j_c) EXPECT_TRUE(std::isfinite(j));
  }
}

TEST(PhotometricValidityTest, PinholePointBehindTheTargetCamera) {
  // The target looks the opposite way (180° about y), 1 m behind: the point is at z < 0.
  const InvalidCase<Pinhole> c({160.0, 120.0}, poseFrom(0.0, M_PI, 0.0, 0.0, 0.0, -1.0), 0.5);
  expectRejected<Pinhole>(c, PhotometricStatus::kBehindCamera);
}

TEST(PhotometricValidityTest, PointProjectsOutsideTheTargetImage) {
  // 3 m sideways for a point 2 m away: far outside the pinhole's 80° field of view image.
  const InvalidCase<Pinhole> c({160.0, 120.0}, poseFrom(0.0, 0.0, 0.0, 3.0, 0.0, 0.0), 0.5);
  expectRejected<Pinhole>(c, PhotometricStatus::kOutsideImage);
  // Near the border the bilinear footprint of an outer pattern pixel leaves the image.
  const InvalidCase<Pinhole> border({1.0, 120.0}, SE3d(), 0.5);
  expectRejected<Pinhole>(border, PhotometricStatus::kOutsideImage);
}

TEST(PhotometricValidityTest, UcmBeyondItsFold) {
  // ξ = 1.5: projectable up to acos(−1/ξ) ≈ 131.8° off-axis. A host ray at 100° seen from a
  // target rotated 45° away lies at ~145°: beyond the fold, outside the model's domain.
  using Tag = Ucm;
  Tag::Params params = Tag::params();
  params[4] = 1.5;
  const UnifiedCamera<double> camera(params);
  const double theta = 100.0 * M_PI / 180.0;
  Eigen::Vector2d pixel;
  ASSERT_TRUE(camera.project(Eigen::Vector3d(std::sin(theta), 0.0, std::cos(theta)), pixel));
  InvalidCase<Tag> c(pixel, poseFrom(0.0, -M_PI / 4, 0.0, 0.0, 0.0, 0.0), 0.5);
  c.blocks.intrinsics = params;
  expectRejected<Tag>(c, PhotometricStatus::kOutsideDomain);
}

TEST(PhotometricValidityTest, UcmHostPixelOutsideTheImageOfTheSphere) {
  // ξ = 1.5 images the sphere inside r² < 1/(ξ² − 1) = 0.8 (normalised): 120 px out is past it.
  using Tag = Ucm;
  Tag::Params params = Tag::params();
  params[4] = 1.5;
  InvalidCase<Tag> c({params[2] + 120.0, params[3]}, SE3d(), 0.5);
  c.blocks.intrinsics = params;
  expectRejected<Tag>(c, PhotometricStatus::kHostOutsideDomain);
}

// A target pattern pixel whose bilinear cell touches a pixel without content (the black
// surround of a fisheye image) is out of the image: the same residual is valid without the
// mask, and with a mask whose hole lies elsewhere. Both the window's and the tracker's
// residuals check it.
TEST(PhotometricValidityTest, TargetSampleTouchingNonContentIsOutsideTheImage) {
  using Tag = Ucm;
  InvalidCase<Tag> c({160.0, 120.0}, SE3d(), 0.5);  // identity: each pattern pixel on itself
  const auto pointers = c.blocks.pointers();
  ASSERT_EQ(Tag::status(c.obs, pointers.data()), PhotometricStatus::kValid);
  Mask content(kTestWidth, kTestHeight, 1);
  c.obs.target_content = &content;
  content(100, 100) = 0;
  EXPECT_EQ(Tag::status(c.obs, pointers.data()), PhotometricStatus::kValid);
  content(162, 120) = 0;  // pattern offset (2, 0) of DSO's pattern lands on it
  expectRejected<Tag>(c, PhotometricStatus::kOutsideImage);

  const auto camera = Tag::camera();
  HostPatch<1> patch;
  patch.pixel = {162.0, 120.0};
  auto obs = Tag::trackingObservation(camera, patch, 0.5);
  ASSERT_TRUE(obs.has_value());
  obs->target_image = &c.target;
  const std::array<double, 7> pose = poseBlock(SE3d());
  const std::array<double, 2> affine = {0.0, 0.0};
  const double* params[] = {pose.data(), affine.data()};
  double r = 0.0;
  for (DifferentiationMode mode : {DifferentiationMode::kAnalytic, DifferentiationMode::kAutodiff}) {
    obs->target_content = nullptr;
    EXPECT_TRUE(std::unique_ptr<ceres::CostFunction>(Tag::tracking(mode, camera, *obs))
                    ->Evaluate(params, &r, nullptr));
    obs->target_content = &content;
    EXPECT_FALSE(std::unique_ptr<ceres::CostFunction>(Tag::tracking(mode, camera, *obs))
                     ->Evaluate(params, &r, nullptr));
  }
}

TEST(PhotometricValidityTest, NegativeInverseDistance) {
  const InvalidCase<Ucm> c({160.0, 120.0}, SE3d(), -0.1);
  expectRejected<Ucm>(c, PhotometricStatus::kNegativeInverseDistance);
}

TEST(PhotometricValidityTest, StatusNamesAreDistinct) {
  EXPECT_STREQ(toString(PhotometricStatus::kValid), "valid");
  EXPECT_STRNE(toString(PhotometricStatus::kBehindCamera),
               toString(PhotometricStatus::kOutsideDomain));
}

}  // namespace
}  // namespace omnidso::test
