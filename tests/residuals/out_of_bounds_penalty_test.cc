// OutOfBoundsPenalty: transparent where the wrapped residual is valid, a constant outlier-level
// residual with zero Jacobian where it is not — and why that matters to Ceres: a trust-region
// step into a region where one residual is invalid is taken, not rejected.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <limits>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>

namespace omnidso {
namespace {

// r(x) = (0.1 (x − 10), 0.1 x), valid only for x < 5 (as a projection is valid only inside
// the image).
class BoundedCost final : public ceres::SizedCostFunction<2, 1> {
 public:
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    const double x = p[0][0];
    if (!(x < 5.0)) return false;
    r[0] = 0.1 * (x - 10.0);
    r[1] = 0.1 * x;
    if (j && j[0]) {
      j[0][0] = 0.1;
      j[0][1] = 0.1;
    }
    return true;
  }
};

// r = x − 10: pulls x to 10, through the region where BoundedCost is invalid.
class PullCost final : public ceres::SizedCostFunction<1, 1> {
 public:
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    r[0] = p[0][0] - 10.0;
    if (j && j[0]) j[0][0] = 1.0;
    return true;
  }
};

TEST(OutOfBoundsPenalty, PassesValidEvaluationsThrough) {
  const OutOfBoundsPenalty cost(new BoundedCost, 144.0);
  ASSERT_EQ(cost.num_residuals(), 2);
  ASSERT_EQ(cost.parameter_block_sizes(), std::vector<int32_t>{1});
  double x = 2.0, r[2], j[2];
  const double* p[] = {&x};
  double* jac[] = {j};
  ASSERT_TRUE(cost.Evaluate(p, r, jac));
  EXPECT_DOUBLE_EQ(r[0], -0.8);
  EXPECT_DOUBLE_EQ(r[1], 0.2);
  EXPECT_DOUBLE_EQ(j[0], 0.1);
  EXPECT_DOUBLE_EQ(j[1], 0.1);
  EXPECT_DOUBLE_EQ(cost.rawEnergy(p), 0.8 * 0.8 + 0.2 * 0.2);
}

TEST(OutOfBoundsPenalty, GivesThePenaltyEnergyAndZeroJacobianWhereInvalid) {
  const double energy = 144.0 * 2;
  const OutOfBoundsPenalty cost(new BoundedCost, energy);
  double x = 7.0, r[2], j[2] = {1.0, 1.0};
  const double* p[] = {&x};
  double* jac[] = {j};
  ASSERT_TRUE(cost.Evaluate(p, r, jac));
  EXPECT_NEAR(r[0] * r[0] + r[1] * r[1], energy, 1e-12 * energy);
  EXPECT_EQ(j[0], 0.0);
  EXPECT_EQ(j[1], 0.0);
  EXPECT_TRUE(cost.Evaluate(p, r, nullptr));
  EXPECT_EQ(cost.rawEnergy(p), std::numeric_limits<double>::infinity());
  EXPECT_FALSE(cost.inner().Evaluate(p, r, nullptr));
}

// x starts at 0; the Gauss–Newton step lands near 10, where BoundedCost is invalid. Its cost
// there (the penalty, ½·0.5 = 0.25) is far below what the step saves (½·100 → ≈0), so the
// step must be accepted at once. Unwrapped, Ceres rejects every step that crosses x = 5 and
// can only creep up to the boundary.
double solveFromZero(bool wrapped, ceres::Solver::Summary* summary) {
  double x = 0.0;
  ceres::Problem problem;
  problem.AddResidualBlock(new PullCost, nullptr, &x);
  ceres::CostFunction* bounded = new BoundedCost;
  if (wrapped) bounded = new OutOfBoundsPenalty(bounded, 0.5);
  problem.AddResidualBlock(bounded, nullptr, &x);
  ceres::Solver::Options options;
  options.max_num_iterations = 6;
  options.logging_type = ceres::SILENT;
  ceres::Solve(options, &problem, summary);
  return x;
}

TEST(OutOfBoundsPenalty, LetsTheTrustRegionStepThroughAnInvalidResidual) {
  ceres::Solver::Summary wrapped, bare;
  const double x_wrapped = solveFromZero(true, &wrapped);
  const double x_bare = solveFromZero(false, &bare);
  // Past the boundary the only informative residual is x − 10, which Levenberg–Marquardt's
  // damping (initial μ = 1e-4) lets converge geometrically: within 1e-4 after 6 iterations.
  EXPECT_NEAR(x_wrapped, 10.0, 1e-4);
  EXPECT_EQ(wrapped.num_unsuccessful_steps, 0);
  EXPECT_LT(x_bare, 5.0);
  EXPECT_GT(bare.num_unsuccessful_steps, 0);
}

}  // namespace
}  // namespace omnidso
