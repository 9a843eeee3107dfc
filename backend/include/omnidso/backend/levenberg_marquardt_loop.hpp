#pragma once
// The iterations of Ceres 2.1's TrustRegionMinimizer with the Levenberg–Marquardt strategy
// (trust_region_minimizer.cc), after iteration 0, for the native solvers whose state is a
// small fixed system (frontend/tracker_solver.hpp, frontend/initializer_solver.hpp). At the
// end of every iteration the termination tests in Ceres's order (iterations, gradient,
// trust region); within one: the damped step and its predicted decrease L, its validity
// (a finite step with L > 0; max_num_consecutive_invalid_steps invalid ones fail), the
// candidate x ⊞ δ and its cost, the parameter and function tolerances, then accept
// (ρ = ΔE / L > min_relative_decrease) or reject and the trust-region update
// (trust_region.hpp). The candidate's normal equations are formed except in the last
// iteration, where they would go unused (window_solver.hpp explains).
//
// The problem holds x, its normal equations, the step and the candidate:
//   bool step(const LevenbergMarquardtDamping&, double* model_cost_change)
//       δ and L at x; false where the step is not finite (L then unused)
//   bool evaluateCandidate(bool linearize, double* cost)
//       x ⊞ δ and its cost, with its normal equations when `linearize`; false where it
//       cannot be evaluated
//   double candidateDistance() const        ‖(x ⊞ δ) − x‖
//   void accept(bool linearized)             x ← x ⊞ δ (and its equations when linearized)
//   double norm() const                      ‖x‖
//   double gradientMaxNorm() const           Ceres's ‖x − (x ⊞ −g)‖_∞ at x

#include <algorithm>
#include <cmath>
#include <limits>
#include <omnidso/backend/trust_region.hpp>

namespace omnidso {

enum class LevenbergMarquardtTermination { kConvergence, kNoConvergence, kFailure };

struct LevenbergMarquardtRun {
  LevenbergMarquardtTermination termination = LevenbergMarquardtTermination::kFailure;
  int iterations = 0;          // Ceres: summary.iterations.size() − 1
  int successful_steps = 0;    // Ceres: num_successful_steps (iteration 0 included)
  int unsuccessful_steps = 0;
  double final_cost = 0.0;     // the least cost of any iteration
};

// The run's counts and final cost into a solver's summary with fields of these names
// (TrackerSolverSummary, InitializerSolverSummary); each solver maps the termination itself.
template <class Summary>
void recordRun(const LevenbergMarquardtRun& run, Summary* summary) {
  summary->iterations = run.iterations;
  summary->successful_steps = run.successful_steps;
  summary->unsuccessful_steps = run.unsuccessful_steps;
  summary->final_cost = run.final_cost;
}

// Runs from x with cost `x_cost` and its normal equations (iteration 0, the caller's).
template <class Problem>
LevenbergMarquardtRun runLevenbergMarquardt(Problem& problem,
                                            const LevenbergMarquardtOptions& options,
                                            double x_cost) {
  using Termination = LevenbergMarquardtTermination;
  LevenbergMarquardtRun run;
  double gradient_max_norm = problem.gradientMaxNorm();
  double x_norm = -1.0;  // Ceres's ‖x‖ until a step is accepted
  TrustRegion region{options.initial_trust_region_radius};
  LevenbergMarquardtDamping damping{region.radius, options.min_lm_diagonal,
                                    options.max_lm_diagonal};
  double iteration_cost = x_cost, least_cost = x_cost;
  bool step_successful = true;
  int iteration = 0, consecutive_invalid_steps = 0;

  while (true) {
    // The end of an iteration: record it, then the termination tests in Ceres's order.
    (step_successful ? run.successful_steps : run.unsuccessful_steps) += 1;
    least_cost = std::min(least_cost, iteration_cost);
    if (iteration >= options.max_num_iterations) {
      run.termination = Termination::kNoConvergence;
      break;
    }
    if (step_successful && gradient_max_norm <= options.gradient_tolerance) {
      run.termination = Termination::kConvergence;
      break;
    }
    if (region.radius <= options.min_trust_region_radius) {
      run.termination = Termination::kConvergence;
      break;
    }
    ++iteration;

    // The step and the model's predicted decrease.
    damping.radius = region.radius;
    double model_cost_change = 0.0;
    bool step_valid = problem.step(damping, &model_cost_change);
    if (!step_valid) model_cost_change = 0.0;
    step_valid = step_valid && model_cost_change > 0.0;
    if (!step_valid) {
      if (++consecutive_invalid_steps >= options.max_num_consecutive_invalid_steps) {
        run.termination = Termination::kFailure;  // the start stays in place
        break;
      }
      region.stepRejected();
      step_successful = false;
      iteration_cost = x_cost;
      continue;
    }
    consecutive_invalid_steps = 0;

    // The candidate x ⊞ δ, linearised unless this is the last iteration.
    const bool linearize_candidate = iteration < options.max_num_iterations;
    double candidate_cost = std::numeric_limits<double>::max();
    bool candidate_linearized = problem.evaluateCandidate(linearize_candidate, &candidate_cost);
    if (!candidate_linearized) candidate_cost = std::numeric_limits<double>::max();
    candidate_linearized = candidate_linearized && linearize_candidate;
    if (problem.candidateDistance() <=
        options.parameter_tolerance * (x_norm + options.parameter_tolerance)) {
      run.termination = Termination::kConvergence;
      break;
    }
    const double cost_change = x_cost - candidate_cost;
    if (std::abs(cost_change) <= options.function_tolerance * x_cost) {
      run.termination = Termination::kConvergence;
      break;
    }

    // Accept or reject.
    const double step_quality = candidate_cost >= std::numeric_limits<double>::max()
                                    ? std::numeric_limits<double>::lowest()
                                    : cost_change / model_cost_change;
    if (step_quality > options.min_relative_decrease) {
      problem.accept(candidate_linearized);
      x_norm = problem.norm();
      x_cost = candidate_cost;
      // Without the candidate's equations (the last iteration) the gradient goes unused.
      if (candidate_linearized) gradient_max_norm = problem.gradientMaxNorm();
      step_successful = true;
      iteration_cost = x_cost;
      region.stepAccepted(step_quality, options.max_trust_region_radius);
    } else {
      step_successful = false;
      iteration_cost = candidate_cost;
      region.stepRejected();
    }
  }
  run.iterations = run.successful_steps + run.unsuccessful_steps - 1;
  run.final_cost = least_cost;
  return run;
}

}  // namespace omnidso
