// Marginalisation (backend/marginalizer.hpp) against the full problem and against
// ceres::Covariance. Linear-Gaussian problems make marginalisation exact, so the tolerances
// are set by the solver's convergence (1e-10 tolerances) and double rounding, not by the
// approximation: 1e-6 leaves ample margin.
#include <ceres/ceres.h>
#include <ceres/covariance.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <omnidso/backend/marginalization_prior.hpp>
#include <omnidso/backend/marginalizer.hpp>
#include <random>

namespace omnidso {
namespace {

// r = A·[x_0; x_1; …] − b over the given blocks (all Euclidean).
class LinearCost : public ceres::CostFunction {
 public:
  LinearCost(Eigen::MatrixXd A, Eigen::VectorXd b, std::vector<int> sizes)
      : A_(std::move(A)), b_(std::move(b)) {
    for (int s : sizes) mutable_parameter_block_sizes()->push_back(s);
    set_num_residuals(static_cast<int>(A_.rows()));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::Map<Eigen::VectorXd> r(residuals, num_residuals());
    r = -b_;
    int col = 0;
    for (size_t k = 0; k < parameter_block_sizes().size(); ++k) {
      const int n = parameter_block_sizes()[k];
      r += A_.middleCols(col, n) * Eigen::Map<const Eigen::VectorXd>(x[k], n);
      if (jacobians && jacobians[k]) {
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            jacobians[k], num_residuals(), n) = A_.middleCols(col, n);
      }
      col += n;
    }
    return true;
  }

 private:
  Eigen::MatrixXd A_;
  Eigen::VectorXd b_;
};

// The Jacobian of the problem's residuals (per `eval`), dense.
Eigen::MatrixXd denseJacobian(ceres::Problem& problem,
                              const ceres::Problem::EvaluateOptions& eval) {
  ceres::CRSMatrix crs;
  EXPECT_TRUE(problem.Evaluate(eval, nullptr, nullptr, nullptr, &crs));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) J(row, crs.cols[k]) = crs.values[k];
  return J;
}

struct ChainProblem {
  // Blocks: x0 (3), x1 (2), x2 (2), x3 (1); residuals on {x0}, {x0,x1}, {x1,x2}, {x0,x2},
  // {x2,x3}, {x3}: a small graph where x0 has a Markov blanket {x1, x2}.
  std::vector<Eigen::VectorXd> values;
  std::vector<std::tuple<std::vector<int>, Eigen::MatrixXd, Eigen::VectorXd>> factors;

  explicit ChainProblem(unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    const std::vector<int> sizes = {3, 2, 2, 1};
    for (int s : sizes) {
      Eigen::VectorXd v(s);
      for (int i = 0; i < s; ++i) v[i] = n(rng);
      values.push_back(v);
    }
    const std::vector<std::vector<int>> graph = {{0}, {0, 1}, {1, 2}, {0, 2}, {2, 3}, {3}};
    for (const auto& blocks : graph) {
      int cols = 0;
      for (int b : blocks) cols += sizes[b];
      const int rows = cols + 1;
      Eigen::MatrixXd A(rows, cols);
      Eigen::VectorXd b(rows);
      for (int i = 0; i < A.size(); ++i) A.data()[i] = n(rng);
      for (int i = 0; i < rows; ++i) b[i] = n(rng);
      factors.emplace_back(blocks, A, b);
    }
  }

  void build(ceres::Problem& problem, std::vector<Eigen::VectorXd>& x) const {
    x = values;
    for (auto& v : x) v.setZero();  // start away from the optimum
    for (const auto& [blocks, A, b] : factors) {
      std::vector<int> sizes;
      std::vector<double*> ptrs;
      for (int k : blocks) {
        sizes.push_back(static_cast<int>(x[k].size()));
        ptrs.push_back(x[k].data());
      }
      problem.AddResidualBlock(new LinearCost(A, b, sizes), nullptr, ptrs);
    }
  }
};

void solveTightly(ceres::Problem& problem) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.max_num_iterations = 50;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
}

TEST(Marginalization, LinearGaussianMarginalizeThenOptimizeEqualsFullOptimum) {
  const ChainProblem chain(7);
  ceres::Problem full;
  std::vector<Eigen::VectorXd> x_full;
  chain.build(full, x_full);
  solveTightly(full);

  ceres::Problem reduced;
  std::vector<Eigen::VectorXd> x;
  chain.build(reduced, x);
  Marginalizer marginalizer;
  MarginalizationStats stats;
  ASSERT_NE(marginalizer.marginalize(reduced, {x[0].data()}, &stats), nullptr);
  EXPECT_EQ(stats.num_residual_blocks, 3);  // {x0}, {x0,x1}, {x0,x2}
  EXPECT_EQ(stats.num_prior_blocks, 2);     // x1, x2
  EXPECT_EQ(stats.prior_rank, 4);
  EXPECT_EQ(reduced.NumParameterBlocks(), 3);
  solveTightly(reduced);
  for (int k = 1; k < 4; ++k)
    EXPECT_LT((x[k] - x_full[k]).norm(), 1e-6) << "block " << k;
}

TEST(Marginalization, SuccessiveMarginalizationsAccumulatePriors) {
  // Marginalise x0, then x1 (which the first prior touches): the second prior must fold
  // the first one in, and x2, x3 must still reach the full optimum.
  const ChainProblem chain(11);
  ceres::Problem full;
  std::vector<Eigen::VectorXd> x_full;
  chain.build(full, x_full);
  solveTightly(full);

  ceres::Problem reduced;
  std::vector<Eigen::VectorXd> x;
  chain.build(reduced, x);
  Marginalizer marginalizer;
  marginalizer.marginalize(reduced, {x[0].data()});
  solveTightly(reduced);  // moves x1, x2 away from their linearisation points
  ASSERT_NE(marginalizer.linearizationPoint(x[1].data()), nullptr);
  marginalizer.marginalize(reduced, {x[1].data()});
  EXPECT_EQ(reduced.NumResidualBlocks(), 3);  // {x2,x3}, {x3}, prior on x2
  solveTightly(reduced);
  EXPECT_LT((x[2] - x_full[2]).norm(), 1e-6);
  EXPECT_LT((x[3] - x_full[3]).norm(), 1e-6);
}

TEST(Marginalization, ManyPointBlocksAtOnceMatchFullOptimum) {
  // Two "frames" (3-vectors) and 40 scalar "points", each point observed from both frames
  // (as a keyframe's points are): H_MM is diagonal and eliminated group by group. One point
  // has no information (its Jacobian column is zero) and must simply vanish.
  std::mt19937 rng(21);
  std::normal_distribution<double> n(0.0, 1.0);
  struct Factor { int point; Eigen::MatrixXd A; Eigen::VectorXd b; };
  std::vector<Factor> factors;
  for (int p = 0; p < 40; ++p) {
    Eigen::MatrixXd A(4, 7);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = n(rng);
    if (p == 17) A.col(6).setZero();
    Eigen::VectorXd b(4);
    for (int i = 0; i < 4; ++i) b[i] = n(rng);
    factors.push_back({p, A, b});
  }
  auto build = [&](ceres::Problem& problem, Eigen::Vector3d& f0, Eigen::Vector3d& f1,
                   std::vector<double>& points) {
    f0.setZero();
    f1.setZero();
    points.assign(40, 0.0);
    for (const Factor& f : factors)
      problem.AddResidualBlock(new LinearCost(f.A, f.b, {3, 3, 1}), nullptr, f0.data(), f1.data(),
                               &points[f.point]);
    // Anchor f0 so that the frames are observable on their own.
    problem.AddResidualBlock(new LinearCost(Eigen::MatrixXd::Identity(3, 3),
                                            Eigen::VectorXd::Ones(3), {3}),
                             nullptr, f0.data());
  };
  ceres::Problem full;
  Eigen::Vector3d f0_full, f1_full;
  std::vector<double> points_full;
  build(full, f0_full, f1_full, points_full);
  full.SetParameterBlockConstant(&points_full[17]);  // no information: keep it out of the solve
  solveTightly(full);

  ceres::Problem reduced;
  Eigen::Vector3d f0, f1;
  std::vector<double> points;
  build(reduced, f0, f1, points);
  std::vector<double*> point_blocks;
  for (double& p : points) point_blocks.push_back(&p);
  MarginalizationStats stats;
  Marginalizer marginalizer;
  marginalizer.marginalize(reduced, point_blocks, &stats);
  EXPECT_EQ(stats.num_prior_blocks, 2);
  EXPECT_EQ(reduced.NumResidualBlocks(), 2);  // the anchor and the prior
  solveTightly(reduced);
  EXPECT_LT((f0 - f0_full).norm(), 1e-6);
  EXPECT_LT((f1 - f1_full).norm(), 1e-6);
}

// Information over the kept blocks of everything that remains after marginalisation
// (prior + untouched residuals) = inverse of the marginal covariance of the full problem.
TEST(Marginalization, PriorInformationEqualsInverseMarginalCovariance) {
  const ChainProblem chain(3);
  ceres::Problem full;
  std::vector<Eigen::VectorXd> x_full;
  chain.build(full, x_full);
  solveTightly(full);
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(cov_options);
  const std::vector<const double*> kept = {x_full[1].data(), x_full[2].data(), x_full[3].data()};
  ASSERT_TRUE(covariance.Compute(kept, &full));
  Eigen::MatrixXd cov(5, 5);
  ASSERT_TRUE(covariance.GetCovarianceMatrix(kept, cov.data()));  // symmetric: order irrelevant

  ceres::Problem reduced;
  std::vector<Eigen::VectorXd> x;
  chain.build(reduced, x);
  Marginalizer marginalizer;
  marginalizer.marginalize(reduced, {x[0].data()});
  ceres::Problem::EvaluateOptions eval;
  eval.parameter_blocks = {x[1].data(), x[2].data(), x[3].data()};
  const Eigen::MatrixXd J = denseJacobian(reduced, eval);
  const Eigen::MatrixXd information = J.transpose() * J;
  const Eigen::MatrixXd expected = cov.inverse();
  EXPECT_LT((information - expected).norm() / expected.norm(), 1e-6);
}

// A rotation block on a manifold: attitude from direction observations, marginalised at
// the optimum. The prior's tangent information must equal the inverse tangent covariance.
struct DirectionCost {
  DirectionCost(Eigen::Vector3d v, Eigen::Vector3d w) : v_(v), w_(w) {}
  template <typename T>
  bool operator()(const T* q_raw, const T* bias, T* r) const {
    Eigen::Map<const Eigen::Quaternion<T>> q(q_raw);
    const Eigen::Matrix<T, 3, 1> pred = q * v_.cast<T>();
    for (int i = 0; i < 3; ++i) r[i] = pred[i] + bias[i] - T(w_[i]);
    return true;
  }
  Eigen::Vector3d v_, w_;
};

TEST(Marginalization, ManifoldBlockPriorMatchesCovarianceAndKeepsTangentJacobian) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Quaterniond q_true = Eigen::Quaterniond(Eigen::AngleAxisd(0.7,
      Eigen::Vector3d(1, 2, 3).normalized()));
  auto build = [&](ceres::Problem& problem, Eigen::Quaterniond& q, Eigen::Vector3d& bias) {
    std::mt19937 local(9);
    std::normal_distribution<double> m(0.0, 1.0);
    q = Eigen::Quaterniond::Identity();
    bias.setZero();
    for (int i = 0; i < 6; ++i) {
      const Eigen::Vector3d v(m(local), m(local), m(local));
      const Eigen::Vector3d w = q_true * v + 0.01 * Eigen::Vector3d(m(local), m(local), m(local));
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<DirectionCost, 3, 4, 3>(new DirectionCost(v, w)),
          nullptr, q.coeffs().data(), bias.data());
    }
    problem.AddResidualBlock(  // weak prior on the bias
        new ceres::AutoDiffCostFunction<DirectionCost, 3, 4, 3>(
            new DirectionCost(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero())),
        nullptr, q.coeffs().data(), bias.data());
    problem.SetManifold(q.coeffs().data(), new ceres::EigenQuaternionManifold);
  };
  (void)n;
  ceres::Problem full;
  Eigen::Quaterniond q_full;
  Eigen::Vector3d bias_full;
  build(full, q_full, bias_full);
  solveTightly(full);
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(cov_options);
  const double* q_ptr = q_full.coeffs().data();
  ASSERT_TRUE(covariance.Compute({q_ptr}, &full));
  Eigen::Matrix3d cov;
  ASSERT_TRUE(covariance.GetCovarianceMatrixInTangentSpace({q_ptr}, cov.data()));

  ceres::Problem reduced;
  Eigen::Quaterniond q;
  Eigen::Vector3d bias;
  build(reduced, q, bias);
  solveTightly(reduced);
  Marginalizer marginalizer;
  const ceres::ResidualBlockId prior_id = marginalizer.marginalize(reduced, {bias.data()});
  ASSERT_NE(prior_id, nullptr);
  const auto* prior =
      dynamic_cast<const MarginalizationPrior*>(reduced.GetCostFunctionForResidualBlock(prior_id));
  ASSERT_NE(prior, nullptr);
  const Eigen::Matrix3d expected = cov.inverse();
  EXPECT_LT((prior->information() - expected).norm() / expected.norm(), 1e-6);

  // At the linearisation point the ambient Jacobian passes Ceres's gradient check.
  const ceres::Manifold* manifold = reduced.GetManifold(q.coeffs().data());
  ceres::NumericDiffOptions numeric;
  const std::vector<const ceres::Manifold*> manifolds = {manifold};
  ceres::GradientChecker checker(prior, &manifolds, numeric);
  ceres::GradientChecker::ProbeResults results;
  const double* params[] = {q.coeffs().data()};
  EXPECT_TRUE(checker.Probe(params, 1e-7, &results)) << results.error_log;

  // Away from it, the tangent Jacobian stays S (first-estimate Jacobians).
  q = q * Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  ceres::Problem::EvaluateOptions eval;
  eval.residual_blocks = {prior_id};
  eval.parameter_blocks = {q.coeffs().data()};
  const Eigen::MatrixXd J = denseJacobian(reduced, eval);
  EXPECT_LT((J - prior->sqrtInformation()).norm(), 1e-12 * prior->sqrtInformation().norm());
}

// A residual that cannot be evaluated at the current estimate (as a photometric residual
// whose point has left the target image).
class FailingCost : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  bool Evaluate(double const* const*, double*, double**) const override { return false; }
};

// Marginalising blocks with no residual at all (a keyframe whose residuals all went before
// it, with no brightness prior) removes them and adds no prior — and leaves every other
// residual alone (Problem::Evaluate reads an empty residual list as "all residuals").
TEST(Marginalization, BlocksWithoutResidualsLeaveWithoutAPrior) {
  ceres::Problem problem;
  double x = 1.0, y = 2.0;
  problem.AddParameterBlock(&x, 1);
  problem.AddResidualBlock(new LinearCost(Eigen::MatrixXd::Ones(1, 1), Eigen::VectorXd::Ones(1), {1}),
                           nullptr, &y);
  Marginalizer marginalizer;
  MarginalizationStats stats;
  EXPECT_EQ(marginalizer.marginalize(problem, {&x}, &stats), nullptr);
  EXPECT_FALSE(problem.HasParameterBlock(&x));
  EXPECT_TRUE(problem.HasParameterBlock(&y));
  EXPECT_EQ(problem.NumResidualBlocks(), 1);
  EXPECT_EQ(stats.prior_rank, 0);
}

// r = x + y − 3 and r = x (unit weights): x is determined, so y keeps information.
void addSumAndAnchorResiduals(ceres::Problem& problem, double* x, double* y) {
  problem.AddResidualBlock(
      new LinearCost(Eigen::MatrixXd::Ones(1, 2), 3.0 * Eigen::VectorXd::Ones(1), {1, 1}),
      nullptr, x, y);
  problem.AddResidualBlock(
      new LinearCost(Eigen::MatrixXd::Ones(1, 1), Eigen::VectorXd::Zero(1), {1}), nullptr, x);
}

// JᵀJ of the prior's residual block over `blocks` (in their order): the information it adds.
Eigen::MatrixXd priorInformation(ceres::Problem& problem, ceres::ResidualBlockId prior,
                                 const std::vector<double*>& blocks) {
  ceres::Problem::EvaluateOptions eval;
  eval.residual_blocks = {prior};
  eval.parameter_blocks = blocks;
  const Eigen::MatrixXd J = denseJacobian(problem, eval);
  return J.transpose() * J;
}

// A residual that cannot be evaluated is left out of the prior; the prior comes from the
// others alone: here r = x + y − 3 (unit weight) gives the prior information 1 on y.
TEST(Marginalization, UnevaluableResidualsAreLeftOutOfThePrior) {
  ceres::Problem problem;
  double x = 1.0, y = 2.0, z = 0.5;
  addSumAndAnchorResiduals(problem, &x, &y);
  problem.AddResidualBlock(new FailingCost, nullptr, &x, &z);
  Marginalizer marginalizer;
  MarginalizationStats stats;
  const ceres::ResidualBlockId prior = marginalizer.marginalize(problem, {&x}, &stats);
  ASSERT_NE(prior, nullptr);
  EXPECT_EQ(stats.num_unevaluable_residual_blocks, 1);
  EXPECT_FALSE(problem.HasParameterBlock(&x));
  // H = [[2, 1], [1, 1]] over (x, y) → Schur onto y: 1 − 1·1/2 = 0.5. z got no information.
  const Eigen::MatrixXd information = priorInformation(problem, prior, {&y, &z});
  ASSERT_EQ(information.rows(), 2);
  EXPECT_NEAR(information(0, 0), 0.5, 1e-9);
  EXPECT_NEAR(information(1, 1), 0.0, 1e-12);
}

// r = y² + z − 10, defined only for y ≥ 3 (as a photometric residual whose point would leave
// the target image at an older estimate of its pose).
class SquareCostValidAboveThree : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  bool Evaluate(double const* const* p, double* r, double** jacobians) const override {
    const double y = p[0][0], z = p[1][0];
    if (y < 3.0) return false;
    r[0] = y * y + z - 10.0;
    if (jacobians && jacobians[0]) jacobians[0][0] = 2.0 * y;
    if (jacobians && jacobians[1]) jacobians[1][0] = 1.0;
    return true;
  }
};

// Where a residual evaluates at the current estimate but not at a kept block's first-estimate
// point, the prior takes the Jacobian at the current estimate.
TEST(Marginalization, FallsBackToCurrentJacobiansWhereFirstEstimateCannotBeEvaluated) {
  ceres::Problem problem;
  double x = 1.0, y = 2.0, z = 0.5;
  addSumAndAnchorResiduals(problem, &x, &y);
  Marginalizer marginalizer;
  ASSERT_NE(marginalizer.marginalize(problem, {&x}), nullptr);  // y's first estimate: 2
  y = 4.0;
  problem.AddResidualBlock(new SquareCostValidAboveThree, nullptr, &y, &z);
  problem.AddResidualBlock(new LinearCost(Eigen::MatrixXd::Ones(1, 1), Eigen::VectorXd::Zero(1), {1}),
                           nullptr, &z);
  MarginalizationStats stats;
  const ceres::ResidualBlockId prior = marginalizer.marginalize(problem, {&z}, &stats);
  ASSERT_NE(prior, nullptr);
  EXPECT_FALSE(stats.used_first_estimate_jacobians);
  EXPECT_EQ(stats.num_unevaluable_residual_blocks, 0);
  // Rows [∂r/∂z ∂r/∂y] = [1 2y] = [1 8] and [1 0]: H_zz = 2, H_zy = 8, H_yy = 64, so the
  // information on y is 64 − 8²/2 = 32 (the first-estimate point y = 2 would give 8).
  const Eigen::MatrixXd information = priorInformation(problem, prior, {&y});
  ASSERT_EQ(information.cols(), 1);
  EXPECT_NEAR(information(0, 0), 32.0, 1e-9);
}

}  // namespace
}  // namespace omnidso
