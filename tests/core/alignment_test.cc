// Umeyama alignment on copies of a point set under a known transform: exact recovery,
// reflection handling, recovery within noise-derived bounds, degenerate input.
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/core/alignment.hpp>
#include <omnidso/core/error.hpp>
#include <random>

namespace omnidso {
namespace {

Eigen::Matrix3Xd randomPoints(int n, double half_width, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-half_width, half_width);
  Eigen::Matrix3Xd points(3, n);
  for (int i = 0; i < n; ++i) points.col(i) = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
  return points;
}

Eigen::Matrix3Xd transformed(const Sim3d& s, const Eigen::Matrix3Xd& points) {
  Eigen::Matrix3Xd out(3, points.cols());
  for (Eigen::Index i = 0; i < points.cols(); ++i) out.col(i) = s * Eigen::Vector3d(points.col(i));
  return out;
}

double rotationDistance(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

const Sim3d kKnown(2.5, Eigen::Quaterniond(Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 3).normalized())),
                   Eigen::Vector3d(4.0, -3.0, 1.5));

TEST(Alignment, Sim3RecoversAnExactScaledRotatedTranslatedCopy) {
  const Eigen::Matrix3Xd est = randomPoints(50, 5.0, 1);
  const Sim3d s = alignSim3(est, transformed(kKnown, est));
  // Exact data: only rounding (~1e-15 relative) separates the result from the truth.
  EXPECT_NEAR(s.scale(), kKnown.scale(), 1e-9);
  EXPECT_LT(rotationDistance(s.rotation(), kKnown.rotation()), 1e-9);
  EXPECT_LT((s.translation() - kKnown.translation()).norm(), 1e-9);
}

TEST(Alignment, SE3RecoversAnExactRigidCopy) {
  const Eigen::Matrix3Xd est = randomPoints(50, 5.0, 2);
  const Sim3d rigid(1.0, kKnown.rotation(), kKnown.translation());
  const SE3d t = alignSE3(est, transformed(rigid, est));
  EXPECT_LT(rotationDistance(t.rotation(), kKnown.rotation()), 1e-9);
  EXPECT_LT((t.translation() - kKnown.translation()).norm(), 1e-9);
}

TEST(Alignment, PositionYawRecoversYawAndIgnoresOtherRotation) {
  const Eigen::Matrix3Xd est = randomPoints(50, 5.0, 3);
  const Eigen::Quaterniond yaw(Eigen::AngleAxisd(-2.0, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d t(1.0, 2.0, -0.5);
  const SE3d exact = alignPositionYaw(est, transformed(Sim3d(1.0, yaw, t), est));
  EXPECT_LT(rotationDistance(exact.rotation(), yaw), 1e-9);
  EXPECT_LT((exact.translation() - t).norm(), 1e-9);
  // A general rotation still yields a rotation about z only.
  const SE3d fitted = alignPositionYaw(est, transformed(Sim3d(1.0, kKnown.rotation(), t), est));
  EXPECT_LT(std::abs(fitted.rotation().x()) + std::abs(fitted.rotation().y()), 1e-15);
}

TEST(Alignment, ReflectedPlanarPointsGiveAProperRotation) {
  // Planar points and their mirror image y → −y: a reflection, but also exactly a rotation
  // by π about x (z = 0 for all points). Umeyama's sign correction must find the rotation.
  Eigen::Matrix3Xd est = randomPoints(20, 3.0, 4);
  est.row(2).setZero();
  Eigen::Matrix3Xd gt = est;
  gt.row(1) *= -1.0;
  const Sim3d s = alignSim3(est, gt);
  EXPECT_NEAR(s.rotationMatrix().determinant(), 1.0, 1e-12);
  EXPECT_NEAR(s.scale(), 1.0, 1e-12);
  EXPECT_LT((transformed(s, est) - gt).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Alignment, NoisyCopyIsRecoveredWithinNoiseBounds) {
  const int n = 2000;
  const double noise_sigma = 0.01;
  const double half_width = 5.0;
  const Eigen::Matrix3Xd est = randomPoints(n, half_width, 5);
  Eigen::Matrix3Xd gt = transformed(kKnown, est);
  std::mt19937 rng(6);
  std::normal_distribution<double> noise(0.0, noise_sigma);
  for (Eigen::Index i = 0; i < gt.cols(); ++i) {
    gt.col(i) += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  }
  const Sim3d s = alignSim3(est, gt);
  // Least-squares errors scale as σ/√N over the lever arm: the gt-side spread per axis is
  // s·w/√3 (uniform on [−w, w]), so rotation ≈ σ/(√N s w/√3) rad, scale relative likewise,
  // and the translation ≈ √3 σ/√N (3-D mean of the noise) plus the rotation and scale errors
  // times |μ_est| (≈ w/√N, negligible); 3 covers √3 plus that lever arm. Bounds are 5×.
  const double standard = noise_sigma / std::sqrt(static_cast<double>(n));
  const double spread = kKnown.scale() * half_width / std::sqrt(3.0);
  EXPECT_LT(rotationDistance(s.rotation(), kKnown.rotation()), 5.0 * standard / spread);
  EXPECT_LT(std::abs(s.scale() / kKnown.scale() - 1.0), 5.0 * standard / spread);
  EXPECT_LT((s.translation() - kKnown.translation()).norm(), 5.0 * 3.0 * standard);
}

TEST(Alignment, DegenerateInputThrows) {
  const Eigen::Matrix3Xd two = randomPoints(2, 1.0, 7);
  EXPECT_THROW(alignSim3(two, two), Error);
  EXPECT_THROW(alignSE3(two, two), Error);
  Eigen::Matrix3Xd collinear(3, 5);
  for (int i = 0; i < 5; ++i) collinear.col(i) = Eigen::Vector3d(1, 2, 3) * i;
  EXPECT_THROW(alignSim3(collinear, collinear), Error);
  Eigen::Matrix3Xd coincident = Eigen::Matrix3Xd::Ones(3, 5);
  EXPECT_THROW(alignSE3(coincident, coincident), Error);
  const Eigen::Matrix3Xd four = randomPoints(4, 1.0, 8);
  EXPECT_THROW(alignSim3(four, randomPoints(5, 1.0, 9)), Error);  // sizes differ
  EXPECT_THROW(alignPositionYaw(four.leftCols(1), four.leftCols(1)), Error);
  Eigen::Matrix3Xd vertical = Eigen::Matrix3Xd::Zero(3, 4);
  vertical.row(2) << 0, 1, 2, 3;  // same x-y everywhere: the yaw is undetermined
  EXPECT_THROW(alignPositionYaw(vertical, vertical), Error);
  EXPECT_NO_THROW(alignPositionYaw(two, two));  // 2 points suffice for the yaw
}

}  // namespace
}  // namespace omnidso
