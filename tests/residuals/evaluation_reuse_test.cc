// EvaluationReuse + ReusingCostFunction: an iteration-limited Ceres solve skips exactly the
// evaluation after its last step, and ends bit for bit where the same solve without them
// ends — also when steps are rejected and when the solve stops before its iteration limit.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/residuals/evaluation_reuse.hpp>
#include <omnidso/residuals/reusing_cost_function.hpp>

namespace omnidso {
namespace {

struct Counts {
  int evaluations = 0;           // residual blocks × evaluations
  int jacobian_evaluations = 0;  // of them with Jacobians
};

// r = y − exp(m x + c) over the block [m, c]; counts its evaluations.
class ExponentialCost final : public ceres::SizedCostFunction<1, 2> {
 public:
  ExponentialCost(double x, double y, Counts* counts) : x_(x), y_(y), counts_(counts) {}
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    const double e = std::exp(p[0][0] * x_ + p[0][1]);
    r[0] = y_ - e;
    ++counts_->evaluations;
    if (j && j[0]) {
      ++counts_->jacobian_evaluations;
      j[0][0] = -x_ * e;
      j[0][1] = -e;
    }
    return true;
  }

 private:
  double x_, y_;
  Counts* counts_;
};

struct Outcome {
  double m_c[2] = {0.0, 0.0};
  Counts counts;
  long skipped = 0;  // unused Jacobians (0 without reuse)
  ceres::Solver::Summary summary;
};

constexpr int kNumObservations = 40;

// The curve-fitting problem (truth near (0.3, 0.1)), solved from (m0, c0) with or without
// reuse.
Outcome solve(bool with_reuse, int max_iterations, double m0, double c0) {
  Outcome out;
  out.m_c[0] = m0;
  out.m_c[1] = c0;
  EvaluationReuse reuse;
  ceres::Problem::Options problem_options;
  if (with_reuse) problem_options.evaluation_callback = &reuse;
  ceres::Problem problem(problem_options);
  for (int i = 0; i < kNumObservations; ++i) {
    const double x = 0.1 * i;
    const double y = std::exp(0.3 * x + 0.1) + 0.05 * std::sin(7.0 * i);  // fixed "noise"
    ceres::CostFunction* cost = new ExponentialCost(x, y, &out.counts);
    if (with_reuse) cost = new ReusingCostFunction(cost, &reuse);
    problem.AddResidualBlock(cost, nullptr, out.m_c);
  }
  ceres::Solver::Options options;
  options.max_num_iterations = max_iterations;
  options.linear_solver_type = ceres::DENSE_QR;
  options.logging_type = ceres::SILENT;
  reuse.arm(max_iterations);
  ceres::Solve(options, &problem, &out.summary);
  reuse.disarm();
  out.skipped = reuse.skippedJacobians();
  return out;
}

void expectBitForBitEqual(const Outcome& reusing, const Outcome& plain) {
  EXPECT_EQ(reusing.m_c[0], plain.m_c[0]);
  EXPECT_EQ(reusing.m_c[1], plain.m_c[1]);
  EXPECT_EQ(reusing.summary.final_cost, plain.summary.final_cost);
  ASSERT_EQ(reusing.summary.iterations.size(), plain.summary.iterations.size());
  for (size_t i = 0; i < plain.summary.iterations.size(); ++i)
    EXPECT_EQ(reusing.summary.iterations[i].cost, plain.summary.iterations[i].cost) << i;
  EXPECT_EQ(reusing.summary.num_successful_steps, plain.summary.num_successful_steps);
}

TEST(EvaluationReuse, SkipsOnlyTheEvaluationAfterTheLastAllowedStep) {
  for (int max_iterations : {1, 2, 3, 4}) {
    SCOPED_TRACE(max_iterations);
    const Outcome plain = solve(false, max_iterations, 0.2, 0.0);
    const Outcome reusing = solve(true, max_iterations, 0.2, 0.0);
    // Precondition: every step accepted, so the plain solve evaluated residuals and
    // Jacobian at the start and after each step, and residuals at each candidate.
    ASSERT_EQ(plain.summary.num_successful_steps, max_iterations + 1);  // with iteration 0
    ASSERT_EQ(plain.counts.jacobian_evaluations, (max_iterations + 1) * kNumObservations);
    ASSERT_EQ(plain.counts.evaluations, (2 * max_iterations + 1) * kNumObservations);
    // With reuse: all but the last re-evaluation.
    EXPECT_EQ(reusing.counts.evaluations, 2 * max_iterations * kNumObservations);
    EXPECT_EQ(reusing.counts.jacobian_evaluations, max_iterations * kNumObservations);
    EXPECT_EQ(reusing.skipped, 1);
    expectBitForBitEqual(reusing, plain);
  }
}

TEST(EvaluationReuse, MatchesThePlainSolveWhenStepsAreRejected) {
  // From (0, 0) the first Gauss–Newton steps overshoot the exponential and are rejected
  // (the trust region shrinks), later ones are accepted: a rejected iteration evaluates a
  // candidate but no Jacobian. Whatever the limit, exactly the evaluation after an accepted
  // last step is skipped.
  int rejected_then_skipped = 0;
  for (int max_iterations = 1; max_iterations <= 12; ++max_iterations) {
    SCOPED_TRACE(max_iterations);
    const Outcome plain = solve(false, max_iterations, 0.0, 0.0);
    const Outcome reusing = solve(true, max_iterations, 0.0, 0.0);
    const bool stopped_at_limit =
        static_cast<int>(plain.summary.iterations.size()) - 1 == max_iterations;
    const bool last_step_accepted = plain.summary.iterations.back().step_is_successful;
    EXPECT_EQ(reusing.skipped, stopped_at_limit && last_step_accepted ? 1 : 0);
    EXPECT_EQ(reusing.counts.evaluations,
              plain.counts.evaluations - reusing.skipped * kNumObservations);
    EXPECT_EQ(reusing.counts.jacobian_evaluations,
              plain.counts.jacobian_evaluations - reusing.skipped * kNumObservations);
    expectBitForBitEqual(reusing, plain);
    if (plain.summary.num_unsuccessful_steps > 0 && reusing.skipped == 1) ++rejected_then_skipped;
  }
  EXPECT_GT(rejected_then_skipped, 0) << "no solve with rejected steps reached its limit";
}

TEST(EvaluationReuse, SkipsNothingWhenTheSolveConvergesBeforeTheLimit) {
  const Outcome plain = solve(false, 100, 0.2, 0.0);
  const Outcome reusing = solve(true, 100, 0.2, 0.0);
  ASSERT_LT(static_cast<int>(plain.summary.iterations.size()) - 1, 100);  // converged
  EXPECT_EQ(reusing.skipped, 0);
  EXPECT_EQ(reusing.counts.evaluations, plain.counts.evaluations);
  expectBitForBitEqual(reusing, plain);
}

TEST(ReusingCostFunction, FollowsTheCallbackStepByStep) {
  EvaluationReuse reuse;
  Counts counts;
  const ReusingCostFunction cost(new ExponentialCost(0.5, 2.0, &counts), &reuse);
  double m_c[2] = {0.3, 0.1}, r = 0.0, j[2] = {0.0, 0.0};
  const double* p[] = {m_c};
  double* jac[] = {j};
  auto y = [&] { return std::exp(m_c[0] * 0.5 + m_c[1]); };

  // Disarmed (Problem::Evaluate outside a solve): every evaluation as asked.
  reuse.PrepareForEvaluation(true, true);
  ASSERT_TRUE(cost.Evaluate(p, &r, jac));
  ASSERT_TRUE(cost.Evaluate(p, &r, nullptr));
  EXPECT_EQ(counts.evaluations, 2);
  EXPECT_EQ(counts.jacobian_evaluations, 1);
  EXPECT_EQ(j[1], -y());

  // Armed for 2 iterations, both accepted.
  reuse.arm(2);
  reuse.PrepareForEvaluation(true, true);  // iteration 0
  ASSERT_TRUE(cost.Evaluate(p, &r, jac));
  m_c[0] = 0.4;  // candidate 1 and its re-evaluation: as asked
  reuse.PrepareForEvaluation(false, true);
  EXPECT_FALSE(reuse.keepResiduals());
  ASSERT_TRUE(cost.Evaluate(p, &r, nullptr));
  reuse.PrepareForEvaluation(true, false);
  EXPECT_FALSE(reuse.jacobiansUnused());
  ASSERT_TRUE(cost.Evaluate(p, &r, jac));
  EXPECT_EQ(counts.evaluations, 5);
  EXPECT_EQ(counts.jacobian_evaluations, 3);
  EXPECT_EQ(j[1], -y());
  m_c[0] = 0.5;  // candidate 2, the last: its residuals are kept
  reuse.PrepareForEvaluation(false, true);
  EXPECT_TRUE(reuse.keepResiduals());
  ASSERT_TRUE(cost.Evaluate(p, &r, nullptr));
  EXPECT_EQ(counts.evaluations, 6);
  reuse.PrepareForEvaluation(true, false);  // accepted: residuals copied, Jacobian unused
  EXPECT_TRUE(reuse.jacobiansUnused());
  r = 0.0;
  ASSERT_TRUE(cost.Evaluate(p, &r, jac));
  EXPECT_EQ(counts.evaluations, 6);
  EXPECT_EQ(r, 2.0 - y());
  EXPECT_EQ(j[0], 0.0);
  EXPECT_EQ(j[1], 0.0);
  EXPECT_EQ(reuse.skippedJacobians(), 1);

  // Disarmed again: nothing kept is used.
  reuse.disarm();
  reuse.PrepareForEvaluation(true, false);
  ASSERT_TRUE(cost.Evaluate(p, &r, jac));
  EXPECT_EQ(counts.evaluations, 7);
  EXPECT_EQ(j[1], -y());
}

}  // namespace
}  // namespace omnidso
