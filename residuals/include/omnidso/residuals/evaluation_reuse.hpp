#pragma once
// The evaluation that an iteration-limited Levenberg–Marquardt solve in Ceres makes and never
// uses, and the plan by which cost functions avoid it (ReusingCostFunction).
//
// Ceres's trust-region minimizer (2.1, trust_region_minimizer.cc) evaluates, per iteration,
// the residuals at the candidate point x + Δ (residuals only); if the step is accepted, it
// evaluates residuals and Jacobian again at that same point (HandleSuccessfulStep, with
// new_evaluation_point = false), and only then checks the iteration limit
// (FinalizeIterationAndCheckIfMinimizerCanContinue tests the limit before the gradient
// tolerance). So after the last allowed step that evaluation feeds nothing but the cost,
// known from the candidate, and the gradient norm of the final iteration summary. With 2
// iterations a solve costs 3 Jacobian and 2 residual evaluations; the third Jacobian is
// unused. The plan: the last candidate keeps its residuals (keepResiduals()); the
// evaluation after it (jacobiansUnused()) copies them and returns zero Jacobians.
//
// (Also computing the Jacobian at every candidate, so that the evaluation after an accepted
// step could copy it, saved nothing on the window: Ceres's own work per residual block,
// which a copy does not avoid, is about half of a Jacobian evaluation; docs/performance.md.)
//
// The count: armed with the solve's iteration limit, this evaluation callback counts the
// residual-only evaluations after the first Jacobian evaluation; each is the candidate of
// one iteration (an iteration with an invalid step evaluates none, so the count can lag the
// iteration number, never lead it: a needed Jacobian is never skipped). Before the first
// Jacobian, Ceres may evaluate the residual blocks whose parameters are all constant
// (Program::RemoveFixedBlocks): not an iteration, not counted.
//
// Solutions are bit for bit those of a solve without the callback (evaluation_reuse_test.cc);
// only Summary's last gradient norm reads 0. Disarmed (outside solves: Problem::Evaluate,
// EvaluateResidualBlock) it asks for nothing special. The callback belongs to the problem
// (ceres::Problem::Options::evaluation_callback).

#include <ceres/evaluation_callback.h>

#include <cstdint>

namespace omnidso {

class EvaluationReuse final : public ceres::EvaluationCallback {
 public:
  // Before ceres::Solve with Solver::Options::max_num_iterations = max_iterations.
  void arm(int max_iterations) {
    max_iterations_ = max_iterations;
    jacobian_evaluations_ = 0;
    residual_evaluations_ = 0;
    keep_residuals_ = false;
    jacobians_unused_ = false;
  }
  // After the solve.
  void disarm() {
    max_iterations_ = -1;
    keep_residuals_ = false;
    jacobians_unused_ = false;
  }

  void PrepareForEvaluation(bool evaluate_jacobians, bool new_evaluation_point) override {
    if (new_evaluation_point) ++point_;
    keep_residuals_ = false;
    jacobians_unused_ = false;
    if (max_iterations_ < 0) return;
    if (!evaluate_jacobians) {
      if (jacobian_evaluations_ > 0) keep_residuals_ = ++residual_evaluations_ >= max_iterations_;
      return;
    }
    jacobians_unused_ = jacobian_evaluations_ > 0 && residual_evaluations_ >= max_iterations_;
    ++jacobian_evaluations_;
    if (jacobians_unused_) ++skipped_jacobians_;
  }

  // True while Ceres evaluates the residuals of the last allowed candidate point.
  bool keepResiduals() const { return keep_residuals_; }
  // The current evaluation point; a new number for every new point.
  std::uint64_t point() const { return point_; }
  // True while Ceres asks for a Jacobian it will not use.
  bool jacobiansUnused() const { return jacobians_unused_; }
  // Unused Jacobian evaluations since construction.
  long skippedJacobians() const { return skipped_jacobians_; }

 private:
  int max_iterations_ = -1;
  int jacobian_evaluations_ = 0;
  int residual_evaluations_ = 0;
  std::uint64_t point_ = 0;
  bool keep_residuals_ = false;
  bool jacobians_unused_ = false;
  long skipped_jacobians_ = 0;
};

}  // namespace omnidso
