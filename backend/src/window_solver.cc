// The native window solver's Levenberg–Marquardt loop (window_solver.hpp): iteration 0, then
// per iteration the step, its validity, the candidate, the tolerances, accept or reject and
// the trust-region update, in the order of Ceres 2.1's TrustRegionMinimizer.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <omnidso/backend/trust_region.hpp>
#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_objective.hpp>
#include <omnidso/backend/window_solver.hpp>
#include <omnidso/backend/window_state.hpp>
#include <omnidso/core/timing.hpp>
#include <vector>

namespace omnidso {
namespace {

template <typename... Args>
std::string format(const char* pattern, Args... args) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), pattern, args...);
  return buffer;
}

}  // namespace

WindowSolverSummary solveWindow(const WindowProblem& problem, const WindowSolverOptions& options,
                                WindowSolverWorkspace* workspace,
                                const WindowProblem* first_estimate) {
  const Stopwatch clock;
  WindowSolverSummary summary;
  WindowState state(problem);
  // The normal equations at x, and at the candidate x ⊞ δ (reset by every evaluation).
  WindowSolverWorkspace local;
  if (!workspace) workspace = &local;
  WindowNormalEquations& equations = workspace->equations;
  WindowNormalEquations& candidate_equations = workspace->candidate_equations;
  std::vector<double> start, x;
  // The residuals' raw energies at x and at the candidate (summary.residual_energies).
  std::vector<double> energies, candidate_energies;
  state.save(&start);
  auto evaluate = [&](WindowNormalEquations* at, WindowCost* cost, std::vector<double>* e) {
    const Stopwatch watch;
    const bool ok = evaluateWindow(problem, at, cost, e, first_estimate);
    summary.evaluation_ms += watch.elapsedMs();
    return ok;
  };
  auto fail = [&](std::string message) {
    summary.termination = WindowTermination::kFailure;
    summary.message = std::move(message);
    state.restore(start);
  };

  // Iteration 0.
  WindowCost cost;
  if (!evaluate(&equations, &cost, &energies)) {
    fail("Residual and Jacobian evaluation failed.");
    return summary;
  }
  const double fixed_cost = cost.fixed;
  double x_cost = cost.variable;
  double gradient_max_norm = state.gradientMaxNorm(equations);
  summary.initial_cost = x_cost + fixed_cost;
  // Ceres's minimiser starts with ‖x‖ = −1, so the parameter tolerance cannot end the first
  // iteration.
  double x_norm = -1.0;
  TrustRegion region{options.initial_trust_region_radius};
  LevenbergMarquardtDamping damping{region.radius, options.min_lm_diagonal, options.max_lm_diagonal};
  std::vector<double> iteration_costs;
  double iteration_cost = summary.initial_cost;
  bool step_successful = true;
  int iteration = 0, consecutive_invalid_steps = 0;
  Eigen::VectorXd frame_step, point_step;

  while (true) {
    // The end of an iteration: record it, then the termination tests in Ceres's order.
    (step_successful ? summary.successful_steps : summary.unsuccessful_steps) += 1;
    iteration_costs.push_back(iteration_cost);
    const double elapsed_s = 1e-3 * clock.elapsedMs();
    if (elapsed_s >= options.max_solver_time_in_seconds) {
      summary.termination = WindowTermination::kNoConvergence;
      summary.message = format("Maximum solver time reached. Total solver time: %e >= %e.",
                               elapsed_s, options.max_solver_time_in_seconds);
      break;
    }
    if (iteration >= options.max_num_iterations) {
      summary.termination = WindowTermination::kNoConvergence;
      summary.message =
          format("Maximum number of iterations reached. Number of iterations: %d.", iteration);
      break;
    }
    if (step_successful && gradient_max_norm <= options.gradient_tolerance) {
      summary.termination = WindowTermination::kConvergence;
      summary.message = format("Gradient tolerance reached. Gradient max norm: %e <= %e",
                               gradient_max_norm, options.gradient_tolerance);
      break;
    }
    if (region.radius <= options.min_trust_region_radius) {
      summary.termination = WindowTermination::kConvergence;
      summary.message = format("Minimum trust region radius reached. Trust region radius: %e <= %e",
                               region.radius, options.min_trust_region_radius);
      break;
    }
    ++iteration;

    // The step, and whether the model predicts a decrease.
    damping.radius = region.radius;
    const Stopwatch linear_watch;
    bool step_valid = equations.solveStep(state.variables(), damping, &frame_step, &point_step);
    summary.linear_solver_ms += linear_watch.elapsedMs();
    const double model_cost_change =
        step_valid ? equations.modelCostChange(frame_step, point_step) : 0.0;
    step_valid = step_valid && model_cost_change > 0.0;
    if (!step_valid) {
      if (++consecutive_invalid_steps >= options.max_num_consecutive_invalid_steps) {
        fail(format("Number of consecutive invalid steps more than "
                    "Solver::Options::max_num_consecutive_invalid_steps: %d",
                    options.max_num_consecutive_invalid_steps));
        break;
      }
      region.stepRejected();
      step_successful = false;
      iteration_cost = x_cost + fixed_cost;
      continue;
    }
    consecutive_invalid_steps = 0;

    // The candidate x ⊞ δ, with its normal equations unless this is the last iteration: an
    // accepted candidate (nearly every one in the odometry) is the next linearisation point,
    // where Ceres evaluates residuals and Jacobian again; the cost is the same either way.
    state.save(&x);
    state.plus(frame_step, point_step);
    const bool linearize_candidate = iteration < options.max_num_iterations;
    WindowCost candidate;
    bool candidate_linearized = evaluate(linearize_candidate ? &candidate_equations : nullptr,
                                         &candidate, &candidate_energies);
    const double candidate_cost =
        candidate_linearized ? candidate.variable : std::numeric_limits<double>::max();
    candidate_linearized = candidate_linearized && linearize_candidate;
    const double step_norm = state.distanceTo(x);
    const double parameter_tolerance =
        options.parameter_tolerance * (x_norm + options.parameter_tolerance);
    if (step_norm <= parameter_tolerance) {
      state.restore(x);
      summary.termination = WindowTermination::kConvergence;
      summary.message = format("Parameter tolerance reached. Relative step_norm: %e <= %e.",
                               step_norm / (x_norm + options.parameter_tolerance),
                               options.parameter_tolerance);
      break;
    }
    const double cost_change = x_cost - candidate_cost;
    if (std::abs(cost_change) <= options.function_tolerance * x_cost) {
      state.restore(x);
      summary.termination = WindowTermination::kConvergence;
      summary.message = format("Function tolerance reached. |cost_change|/cost: %e <= %e",
                               std::abs(cost_change) / x_cost, options.function_tolerance);
      break;
    }

    // Accept or reject.
    const double step_quality = candidate_cost >= std::numeric_limits<double>::max()
                                    ? std::numeric_limits<double>::lowest()
                                    : cost_change / model_cost_change;
    if (step_quality > options.min_relative_decrease) {
      x_norm = state.norm();
      x_cost = candidate_cost;
      std::swap(energies, candidate_energies);
      if (candidate_linearized) {
        equations.swap(candidate_equations);
        gradient_max_norm = state.gradientMaxNorm(equations);
      }  // else the last iteration: the Jacobian there would go unused
      step_successful = true;
      iteration_cost = x_cost + fixed_cost;
      region.stepAccepted(step_quality, options.max_trust_region_radius);
    } else {
      state.restore(x);
      step_successful = false;
      iteration_cost = candidate_cost + fixed_cost;
      region.stepRejected();
    }
  }

  if (summary.usable()) summary.residual_energies = std::move(energies);
  summary.iterations = static_cast<int>(iteration_costs.size()) - 1;
  summary.final_cost = summary.initial_cost;
  for (double c : iteration_costs) summary.final_cost = std::min(summary.final_cost, c);
  return summary;
}

}  // namespace omnidso
