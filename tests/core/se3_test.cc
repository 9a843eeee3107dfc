#include "omnidso/core/se3.hpp"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace omnidso {
namespace {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// A tangent [rho; phi] with |phi| = angle about a random axis.
Vec6 randomTangent(std::mt19937& rng, double angle) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Vec6 xi;
  xi.head<3>() = Vec3(normal(rng), normal(rng), normal(rng));
  const Vec3 axis = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
  xi.tail<3>() = angle * axis;
  return xi;
}

SE3d randomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(0.0, 3.1);
  return SE3d::exp(randomTangent(rng, angle(rng)));
}

void expectSamePose(const SE3d& a, const SE3d& b, double tol) {
  EXPECT_LE((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), tol)
      << "\n" << a.matrix() << "\nvs\n" << b.matrix();
}

TEST(SE3, LogOfExpRoundTripOverAngles) {
  std::mt19937 rng(1);
  // Near zero (Taylor branches), generic, and close to π (q.w → 0).
  const double angles[] = {0.0, 1e-12, 1e-8, 1e-5, 0.3, 1.0, 2.0, 3.0, M_PI - 1e-4,
                           M_PI - 1e-7};
  for (double angle : angles) {
    for (int trial = 0; trial < 5; ++trial) {
      const Vec6 xi = randomTangent(rng, angle);
      const Vec6 back = SE3d::exp(xi).log();
      // Well conditioned for |phi| < π (atan2 form of the log; V(phi) invertible below
      // 2π); double rounding of O(1) quantities stays far below 1e-8.
      EXPECT_LT((back - xi).cwiseAbs().maxCoeff(), 1e-8) << "angle " << angle;
    }
  }
}

TEST(SE3, ExpOfLogRoundTrip) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 50; ++trial) {
    const SE3d pose = randomPose(rng);
    expectSamePose(SE3d::exp(pose.log()), pose, 1e-10);
  }
  // Exactly π: the log is ambiguous in sign, but exp∘log must give the pose back.
  const SE3d half_turn(Eigen::Quaterniond(0.0, 0.0, 0.0, 1.0), Vec3(1, 2, 3));
  expectSamePose(SE3d::exp(half_turn.log()), half_turn, 1e-10);
  EXPECT_NEAR(half_turn.log().tail<3>().norm(), M_PI, 1e-12);
}

TEST(SE3, ExpOfPureTranslationAndRotation) {
  Vec6 xi = Vec6::Zero();
  xi.head<3>() = Vec3(1, -2, 3);
  expectSamePose(SE3d::exp(xi), SE3d(Eigen::Quaterniond::Identity(), Vec3(1, -2, 3)), 1e-15);
  xi.setZero();
  xi(5) = 0.7;  // rotation by 0.7 rad about z
  const Eigen::Matrix3d rz = Eigen::AngleAxisd(0.7, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_LT((SE3d::exp(xi).rotationMatrix() - rz).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(SE3, CompositionAndInverse) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const SE3d a = randomPose(rng), b = randomPose(rng);
    const Vec3 p(normal(rng), normal(rng), normal(rng));
    expectSamePose(a * a.inverse(), SE3d::identity(), 1e-12);
    expectSamePose(a.inverse() * a, SE3d::identity(), 1e-12);
    EXPECT_LT((a.matrix() * b.matrix() - (a * b).matrix()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(((a * b) * p - a * (b * p)).norm(), 1e-12);
    EXPECT_LT((a.inverse() * (a * p) - p).norm(), 1e-12);
  }
}

TEST(SE3, InterpolationEndpointsAndMidpoint) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    const SE3d a = randomPose(rng), b = randomPose(rng);
    expectSamePose(interpolate(a, b, 0.0), a, 1e-12);
    expectSamePose(interpolate(a, b, 1.0), b, 1e-9);
    // The midpoint splits the relative motion into two equal halves: a⁻¹m = m⁻¹b.
    const SE3d m = interpolate(a, b, 0.5);
    expectSamePose(a.inverse() * m, m.inverse() * b, 1e-9);
    EXPECT_LT(((a.inverse() * m).log() - 0.5 * (a.inverse() * b).log()).norm(), 1e-9);
  }
}

TEST(SE3, ParameterBlockRoundTrip) {
  std::mt19937 rng(5);
  const SE3d pose = randomPose(rng);
  double block[SE3d::kNumParameters];
  pose.toParameters(block);
  EXPECT_DOUBLE_EQ(block[0], pose.rotation().x());  // [qx qy qz qw tx ty tz]
  EXPECT_DOUBLE_EQ(block[3], pose.rotation().w());
  EXPECT_DOUBLE_EQ(block[6], pose.translation().z());
  expectSamePose(SE3d::fromParameters(block), pose, 0.0);
}

TEST(SE3, JetDerivativeOfExpAtZero) {
  // d(exp(ξ)·p)/dξ at ξ = 0 is [I, −[p]×] for ξ = [rho; phi] (rotation R ≈ I + [phi]×
  // and V ≈ I to first order).
  using Jet = ceres::Jet<double, 6>;
  Eigen::Matrix<Jet, 6, 1> xi;
  for (int i = 0; i < 6; ++i) xi(i) = Jet(0.0, i);
  const Vec3 p(0.3, -1.2, 2.5);
  const Eigen::Matrix<Jet, 3, 1> moved = SE3<Jet>::exp(xi) * p.cast<Jet>();
  Eigen::Matrix<double, 3, 6> jacobian;
  for (int r = 0; r < 3; ++r) jacobian.row(r) = moved(r).v.transpose();
  Eigen::Matrix<double, 3, 6> expected;
  expected.leftCols<3>() = Eigen::Matrix3d::Identity();
  expected.rightCols<3>() = -skew(p);
  // The Taylor branch is exact to first order at 0: only rounding remains.
  EXPECT_LT((jacobian - expected).cwiseAbs().maxCoeff(), 1e-14) << jacobian;
  for (int r = 0; r < 3; ++r) EXPECT_DOUBLE_EQ(moved(r).a, p(r));
}

TEST(SE3, JetDerivativeOfExpMatchesCentralDifferences) {
  // Away from zero (the trigonometric branch) against central differences: the error is
  // O(h²)·|third derivative| ≈ 1e-10 plus rounding eps/h ≈ 1e-11.
  using Jet = ceres::Jet<double, 6>;
  std::mt19937 rng(6);
  const Vec6 xi0 = randomTangent(rng, 1.3);
  const Vec3 p(0.5, 0.25, -2.0);
  Eigen::Matrix<Jet, 6, 1> xi;
  for (int i = 0; i < 6; ++i) xi(i) = Jet(xi0(i), i);
  const Eigen::Matrix<Jet, 3, 1> moved = SE3<Jet>::exp(xi) * p.cast<Jet>();
  const double h = 1e-5;
  for (int i = 0; i < 6; ++i) {
    Vec6 plus = xi0, minus = xi0;
    plus(i) += h;
    minus(i) -= h;
    const Vec3 numeric = (SE3d::exp(plus) * p - SE3d::exp(minus) * p) / (2 * h);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(moved(r).v(i), numeric(r), 1e-8);
  }
}

// d(exp(ξ)·p)/dξ by Jets in scalar type S, at ξ = [1 2 3 | angle·(0.6, 0.8, 0)].
template <typename S>
Eigen::Matrix<double, 3, 6> expJacobian(double angle, const Vec3& p) {
  using Jet = ceres::Jet<S, 6>;
  const double xi0[6] = {1.0, 2.0, 3.0, 0.6 * angle, 0.8 * angle, 0.0};
  Eigen::Matrix<Jet, 6, 1> xi;
  for (int i = 0; i < 6; ++i) xi(i) = Jet(S(xi0[i]), i);
  const Eigen::Matrix<Jet, 3, 1> moved = SE3<Jet>::exp(xi) * p.cast<S>().template cast<Jet>();
  Eigen::Matrix<double, 3, 6> jacobian;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 6; ++c) jacobian(r, c) = static_cast<double>(moved(r).v(c));
  return jacobian;
}

TEST(SE3, JetDerivativeAccurateAtSmallAngles) {
  // Just above the Taylor threshold (θ² = 1e-10) a naive 1 − cos θ loses half its digits,
  // which put errors of ~1e-7 into the Jacobian; against a long-double reference the
  // double result must be accurate to ~1e-11 (remaining cancellation in θ − sin θ).
  const Vec3 p(0.3, -1.2, 2.5);
  for (double angle : {1.5e-5, 1e-4, 1e-3}) {
    const auto reference = expJacobian<long double>(angle, p);
    EXPECT_LT((expJacobian<double>(angle, p) - reference).cwiseAbs().maxCoeff(), 1e-10)
        << "angle " << angle;
  }
}

TEST(SE3, CastToFloat) {
  std::mt19937 rng(7);
  const SE3d pose = randomPose(rng);
  const SE3f pose_f = pose.cast<float>();
  // float has ~6e-8 relative precision; entries are O(3).
  EXPECT_LT((pose_f.matrix().cast<double>() - pose.matrix()).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace omnidso
