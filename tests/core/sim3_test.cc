// Sim(3): exp against the 4×4 matrix exponential, exp/log round trips in every branch,
// group laws, action on points and poses, interpolation.
#include <gtest/gtest.h>

#include <omnidso/core/sim3.hpp>
#include <random>
#include <unsupported/Eigen/MatrixFunctions>

namespace omnidso {
namespace {

using Tangent = Sim3d::Tangent;

Tangent makeTangent(const Eigen::Vector3d& rho, const Eigen::Vector3d& phi, double sigma) {
  Tangent xi;
  xi << rho, phi, sigma;
  return xi;
}

// Tangents covering the branches of W: θ and σ zero, tiny (< 1e-8), near the 1e-8 switch,
// small, and large (|σ| > 1 uses the closed-form moments).
std::vector<Tangent> branchTangents() {
  const Eigen::Vector3d rho(0.3, -1.2, 2.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  std::vector<Tangent> out;
  for (const double theta : {0.0, 1e-12, 0.99e-8, 1.01e-8, 1e-5, 0.3, 2.5, 3.1}) {
    for (const double sigma : {0.0, 1e-13, -1e-9, 1e-6, 0.4, -0.9, 1.5, -2.5}) {
      out.push_back(makeTangent(rho, theta * axis, sigma));
    }
  }
  return out;
}

TEST(Sim3, ExpMatchesMatrixExponentialOfGenerator) {
  for (const Tangent& xi : branchTangents()) {
    // Generator [[σI + [φ]x, ρ], [0, 0]] (Lie algebra of Sim(3)).
    Eigen::Matrix4d generator = Eigen::Matrix4d::Zero();
    generator.topLeftCorner<3, 3>() =
        xi(6) * Eigen::Matrix3d::Identity() + skew(Eigen::Vector3d(xi.segment<3>(3)));
    generator.topRightCorner<3, 1>() = xi.head<3>();
    const Eigen::Matrix4d expected = generator.exp();
    // Entries are O(e^2.5 · 3) ≈ 40; Padé and the closed form each err by a few ulps of
    // that, so 1e-12 absolute is ~100× the rounding level.
    EXPECT_LT((Sim3d::exp(xi).matrix() - expected).cwiseAbs().maxCoeff(), 1e-12)
        << xi.transpose();
  }
}

TEST(Sim3, LogInvertsExp) {
  for (const Tangent& xi : branchTangents()) {
    // log(exp(ξ)) = ξ for θ < π; W⁻¹ is well conditioned there, so rounding stays ~1e-15
    // relative; 1e-12 leaves margin for θ = 3.1 where W's conditioning grows.
    EXPECT_LT((Sim3d::exp(xi).log() - xi).norm(), 1e-12) << xi.transpose();
  }
}

TEST(Sim3, GroupLawsAndActions) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto randomTangent = [&] {
    Tangent xi;
    for (int k = 0; k < 7; ++k) xi(k) = normal(rng);
    return xi;
  };
  for (int trial = 0; trial < 20; ++trial) {
    const Sim3d a = Sim3d::exp(randomTangent());
    const Sim3d b = Sim3d::exp(randomTangent());
    const Eigen::Vector3d p(normal(rng), normal(rng), normal(rng));
    // Composition and inverse agree with 4×4 matrix algebra (values O(10), eps-level error).
    EXPECT_LT(((a * b).matrix() - a.matrix() * b.matrix()).norm(), 1e-12);
    EXPECT_LT(((a * a.inverse()).matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-12);
    EXPECT_LT((a * p - (a.matrix() * p.homogeneous()).head<3>()).norm(), 1e-12);
    // On a pose: S·T keeps a rigid rotation and maps the pose's position like a point.
    const SE3d pose = SE3d::exp(randomTangent().head<6>());
    const SE3d moved = a * pose;
    EXPECT_LT((moved.translation() - a * pose.translation()).norm(), 1e-12);
    EXPECT_LT((moved.rotationMatrix() - a.rotationMatrix() * pose.rotationMatrix()).norm(), 1e-12);
  }
}

TEST(Sim3, InterpolateHitsEndpointsAndHalvesTheGeodesic) {
  const Sim3d a = Sim3d::exp(makeTangent({1, 2, 3}, {0.1, -0.2, 0.3}, 0.2));
  const Sim3d b = Sim3d::exp(makeTangent({-1, 0.5, 2}, {0.5, 0.1, -0.4}, -0.3));
  EXPECT_LT((interpolate(a, b, 0.0).matrix() - a.matrix()).norm(), 1e-12);
  EXPECT_LT((interpolate(a, b, 1.0).matrix() - b.matrix()).norm(), 1e-12);
  // m = a·exp(½ log(a⁻¹b)) ⇒ (a⁻¹m)² = a⁻¹b.
  const Sim3d half = a.inverse() * interpolate(a, b, 0.5);
  EXPECT_LT(((half * half).matrix() - (a.inverse() * b).matrix()).norm(), 1e-12);
  // The scale interpolates geometrically: s(½) = √(s_a s_b).
  EXPECT_NEAR(interpolate(a, b, 0.5).scale(), std::sqrt(a.scale() * b.scale()), 1e-14);
}

}  // namespace
}  // namespace omnidso
