// The intrinsics prior: its residual is the scaled displacement from the calibration, and
// its Jacobian passes Ceres's gradient check.
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <omnidso/backend/intrinsics_prior.hpp>

namespace omnidso {
namespace {

TEST(IntrinsicsPrior, ResidualIsPixelDisplacementScaledBySqrtWeight) {
  Eigen::VectorXd calibration(5);
  calibration << 220.0, 224.0, 240.0, 238.0, 0.97;  // fx fy cx cy ξ
  const double weight = 4.0;
  const IntrinsicsPrior prior(calibration, weight);
  Eigen::VectorXd x = calibration;
  x[2] += 1.5;    // cx one and a half pixels off
  x[4] += 0.01;   // ξ off by 0.01: the periphery moves by ≈ f̄ · 0.01 = 2.22 px
  const double* params[] = {x.data()};
  Eigen::VectorXd r(5);
  ASSERT_TRUE(prior.Evaluate(params, r.data(), nullptr));
  EXPECT_NEAR(r[0], 0.0, 1e-12);
  EXPECT_NEAR(r[2], 2.0 * 1.5, 1e-12);
  EXPECT_NEAR(r[4], 2.0 * 222.0 * 0.01, 1e-9);
}

TEST(IntrinsicsPrior, JacobianPassesGradientCheck) {
  Eigen::VectorXd calibration(6);
  calibration << 300.0, 301.0, 320.0, 240.0, 0.6, 1.1;  // EUCM-like: fx fy cx cy α β
  const IntrinsicsPrior prior(calibration, 1e3);
  Eigen::VectorXd x = calibration + Eigen::VectorXd::LinSpaced(6, -0.5, 0.5);
  ceres::NumericDiffOptions numeric;
  const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
  ceres::GradientChecker checker(&prior, no_manifolds, numeric);
  ceres::GradientChecker::ProbeResults results;
  const double* params[] = {x.data()};
  EXPECT_TRUE(checker.Probe(params, 1e-8, &results)) << results.error_log;
}

}  // namespace
}  // namespace omnidso
