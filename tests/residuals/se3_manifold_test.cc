// SE3Manifold: Ceres's manifold invariants (Plus/Minus consistency, Plus/Minus Jacobians
// against Ridders differences, RightMultiplyByPlusJacobian) and the pseudo-inverse P⁺.

#include "omnidso/residuals/se3_manifold.hpp"

#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include <random>

#include "omnidso/core/se3.hpp"

namespace omnidso {
namespace {

using Vector = Eigen::VectorXd;
// The matchers EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD expands to.
using ceres::HasCorrectMinusJacobianAt;
using ceres::HasCorrectPlusJacobianAt;
using ceres::HasCorrectRightMultiplyByPlusJacobianAt;
using ceres::MinusPlusIsIdentityAt;
using ceres::MinusPlusJacobianIsIdentityAt;
using ceres::PlusMinusIsIdentityAt;
using ceres::XMinusXIsZeroAt;
using ceres::XPlusZeroIsXAt;

Vector randomPose(std::mt19937& rng, double rotation_scale) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Vector3d phi(normal(rng), normal(rng), normal(rng));
  const Eigen::Vector3d t(normal(rng), normal(rng), normal(rng));
  Vector x(7);
  SE3d(so3Exp(Eigen::Vector3d(rotation_scale * phi)), t).toParameters(x.data());
  return x;
}

TEST(SE3ManifoldTest, InvariantsHoldAtSeveralPoints) {
  const SE3Manifold manifold;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 0.3);
  // Tolerance: the invariants are identities up to rounding in exp/log (~1e-15) and the
  // Ridders-differentiated Jacobians of the macro, accurate to ~1e-10 on these O(1) maps.
  constexpr double kTolerance = 1e-9;
  for (int i = 0; i < 8; ++i) {
    const Vector x = randomPose(rng, i == 0 ? 0.0 : 1.0);  // includes the identity rotation
    Vector delta(6);
    for (int k = 0; k < 6; ++k) delta[k] = normal(rng);
    // q and −q are the same rotation and Minus returns the shortest one, so Plus(x, Minus(y,
    // x)) reproduces y's storage exactly when q_x* ⊗ q_y has w ≥ 0: take y = x ⊞ (a rotation
    // below π) with a random other pose's translation.
    Vector step(6);
    for (int k = 0; k < 6; ++k) step[k] = 2.0 * normal(rng);
    Vector y(7);
    manifold.Plus(x.data(), step.data(), y.data());
    y.tail<3>() = randomPose(rng, 1.0).tail<3>();
    EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, kTolerance);
  }
}

TEST(SE3ManifoldTest, TangentToAmbientIsLeftInverseOfPlusJacobian) {
  const SE3Manifold manifold;
  std::mt19937 rng(5);
  for (int i = 0; i < 5; ++i) {
    const Vector x = randomPose(rng, 1.0);
    Eigen::Matrix<double, 7, 6, Eigen::RowMajor> P;
    ASSERT_TRUE(manifold.PlusJacobian(x.data(), P.data()));
    // P⁺ P = I exactly in exact arithmetic (unit quaternion); rounding only.
    EXPECT_LT((se3TangentToAmbient(x.data()) * P - Eigen::Matrix<double, 6, 6>::Identity()).norm(),
              1e-14);
  }
}

}  // namespace
}  // namespace omnidso
