// Camera paths: procedural hand-held motion and recorded trajectories placed in the room.
#include <omnidso/synth/motion.hpp>

#include <gtest/gtest.h>

#include <cmath>

#include <omnidso/core/trajectory_io.hpp>

#include "test_data.hpp"

namespace omnidso::synth {
namespace {

const AlignedBox kFreeSpace{Eigen::Vector3d(2.5, 2.0, 0.9), Eigen::Vector3d(5.5, 4.0, 2.0)};

TEST(MotionTest, LevelCameraLooksAlongYawWithYDown) {
  const Eigen::Matrix3d r = levelCameraRotation(M_PI / 2);
  EXPECT_TRUE(r.col(2).isApprox(Eigen::Vector3d(0, 1, 0), 1e-12));   // z forward → world y
  EXPECT_TRUE(r.col(1).isApprox(Eigen::Vector3d(0, 0, -1), 1e-12));  // y down
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
}

// 60 s at 100 Hz: the path stays in the free space (its position is the centre plus at most
// the half size: wave weights sum to one), and it has fast turns. The yaw rate of a burst
// peaks at ≤ max_burst_rate (2.5 rad/s); the slow wander (≤ 0.8 rad at ≤ 0.1 Hz: ≤ 0.5 rad/s)
// and the tremor (0.004 rad at ≤ 8 Hz: ≤ 0.2 rad/s) add to it, and pitch and roll waves
// (≤ 0.42 rad at ≤ 0.3 Hz: ≤ 0.8 rad/s) to the total, so the rate stays below 4 rad/s.
TEST(MotionTest, HandheldMotionStaysInsideAndTurnsFast) {
  HandheldMotionConfig config;
  config.duration_s = 60.0;
  const HandheldMotion motion(kFreeSpace, config, 17);
  double max_rate = 0.0;
  SE3d previous = motion.poseAt(0.0);
  for (int k = 1; k <= 6000; ++k) {
    const SE3d pose = motion.poseAt(k * 0.01);
    ASSERT_TRUE(kFreeSpace.contains(pose.translation())) << "t = " << k * 0.01;
    const double angle = so3Log(previous.rotation().conjugate() * pose.rotation()).norm();
    max_rate = std::max(max_rate, angle / 0.01);
    previous = pose;
  }
  EXPECT_GT(max_rate, 1.5);
  EXPECT_LT(max_rate, 4.0);
}

TEST(MotionTest, HandheldMotionIsReproducibleBySeed) {
  const HandheldMotion a(kFreeSpace, {}, 3);
  const HandheldMotion b(kFreeSpace, {}, 3);
  const HandheldMotion c(kFreeSpace, {}, 4);
  EXPECT_TRUE(a.poseAt(7.3).matrix() == b.poseAt(7.3).matrix());
  EXPECT_FALSE(a.poseAt(7.3).matrix() == c.poseAt(7.3).matrix());
}

// EuRoC's IMU has x up; the chosen camera must look along body z like the real cam0
// (T_BS of V1_01: camera z ≈ body z, camera y ≈ −body x).
TEST(MotionTest, BodyToCameraRotationLooksHorizontallyForEurocBodyFrames) {
  Trajectory body;
  // Body x up in a z-up world, heading varying: R_world_body columns (x, y, z) =
  // (world z, ·, horizontal).
  for (int k = 0; k < 10; ++k) {
    const double heading = 0.3 * k;
    Eigen::Matrix3d r;
    r.col(0) = Eigen::Vector3d::UnitZ();
    r.col(2) = Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
    r.col(1) = r.col(2).cross(r.col(0));
    body.push_back({0.1 * k, SE3d(r, Eigen::Vector3d::Zero())});
  }
  const Eigen::Matrix3d r_body_cam = bodyToCameraRotation(body);
  EXPECT_TRUE(r_body_cam.col(2).isApprox(Eigen::Vector3d::UnitZ(), 1e-9));
  EXPECT_TRUE(r_body_cam.col(1).isApprox(-Eigen::Vector3d::UnitX(), 1e-9));
  EXPECT_NEAR(r_body_cam.determinant(), 1.0, 1e-12);
}

TEST(MotionTest, RecordedTrajectoryIsResampledAndPlacedInTheFreeSpace) {
  const auto dir = test::sharedDataDir("trajectories");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("trajectories");
  for (const char* name :
       {"tumvi_room1_imu_groundtruth.txt", "euroc_v1_01_easy_imu_groundtruth.txt"}) {
    const std::string path = (*dir / name).string();
    const Trajectory body = readTrajectoryTum(path);
    const Trajectory cameras = recordedCameraTrajectory(body, path, kFreeSpace, 20.0, 400, 0.1);
    ASSERT_EQ(cameras.size(), 400u) << name;
    double mean_forward_up = 0.0;
    for (size_t k = 0; k < cameras.size(); ++k) {
      // Frames at t₀ + k/20 (1e-9 s: double rounding of ~1.5e9 s timestamps).
      EXPECT_NEAR(cameras[k].timestamp - cameras[0].timestamp, k / 20.0, 1e-6);
      const Eigen::Vector3d c = cameras[k].pose.translation();
      EXPECT_TRUE((c.array() >= kFreeSpace.min.array() + 0.1 - 1e-9).all() &&
                  (c.array() <= kFreeSpace.max.array() - 0.1 + 1e-9).all())
          << name << " frame " << k;
      mean_forward_up += cameras[k].pose.rotationMatrix().col(2).z() / cameras.size();
    }
    // The camera looks horizontally on average (forward axis ⟂ up).
    EXPECT_LT(std::abs(mean_forward_up), 0.3) << name;
  }
}

}  // namespace
}  // namespace omnidso::synth
