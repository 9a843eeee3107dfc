#pragma once
// The native window solver: Levenberg–Marquardt over SlidingWindow's problem
// (window_problem.hpp) with the points eliminated by the Schur complement, specialised for
// its structure — per residual one evaluation of the 8-pixel kernel with tangent-space
// Jacobians, JᵀJ summed per host–target pair and per point in fixed-size blocks, the
// reduced camera system (8 per keyframe + the intrinsics) dense — instead of Ceres's generic
// per-block evaluation and dynamic-size Schur complement (issue 16: the window solve was
// ≈ 2/3 of a keyframe's mapping time; docs/performance.md, "The native window solver").
//
// It reproduces ceres::Solve with the window's options (Levenberg–Marquardt, DENSE_SCHUR,
// no Jacobi scaling, monotonic steps; Ceres 2.1, trust_region_minimizer.cc and
// levenberg_marquardt_strategy.cc), so the two differ only by rounding:
//  - the cost (window_objective.hpp), its tangent Jacobian and the robust correction;
//  - the step: (JᵀJ + D²) y = Jᵀr, step = −y, D² = clamp(diag JᵀJ, 1e-6, 1e32) / Δ
//    (window_normal_equations.hpp); the trust-region radius Δ starts at 1e4;
//  - a step is invalid when the factorisation fails or the model cost change
//    L = −(Jδ)ᵀ(r + Jδ/2) is not positive: Δ ← Δ/ν, ν ← 2ν; five in a row end the solve
//    as a failure;
//  - the candidate x ⊞ δ: the solve ends (CONVERGENCE, keeping x) when
//    ‖x ⊞ δ − x‖ ≤ ε_p (‖x‖ + ε_p) (ambient; ‖x‖ counts as −1 until a step is accepted, as in
//    Ceres) or |E(x) − E(x ⊞ δ)| ≤ ε_f E(x);
//  - ratio ρ = (E(x) − E(x ⊞ δ)) / L > 1e-3: accepted, Δ ← min(Δ / max(1/3, 1 − (2ρ − 1)³),
//    1e16), ν ← 2; otherwise rejected, Δ ← Δ/ν, ν ← 2ν;
//  - after each iteration: the time limit, then the iteration limit, then ‖x − (x ⊞ −g)‖_∞
//    ≤ 1e-10 (after accepted steps) and Δ ≤ 1e-32 end the solve.
// E excludes Ceres's fixed cost (blocks whose parameters are all constant) in the
// tolerances; the reported costs include it, and the final cost is the least iteration cost
// (Ceres's SetSummaryFinalCost).
// Evaluations: the candidate of every iteration but the last is evaluated with its normal
// equations, so an accepted step — nearly every one in the odometry — needs no second
// evaluation at its point (a rejected one wastes them); the last candidate's cost only:
// its Jacobian would go unused (evaluation_reuse.hpp explains the same for Ceres).
// A failed solve restores the starting values, as Ceres does.
//
// Deterministic: everything is summed in a fixed order (points by id, keyframes oldest first).
// Single-threaded. Level 0 only (SlidingWindow::optimizeCoarseToFine solves its coarser
// levels with Ceres).

#include <limits>
#include <omnidso/backend/trust_region.hpp>
#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_problem.hpp>
#include <string>
#include <vector>

namespace omnidso {

struct WindowSolverOptions : LevenbergMarquardtOptions {  // Ceres's names and defaults
  WindowSolverOptions() { max_num_iterations = 2; }  // the window's (SlidingWindowOptions)
  double max_solver_time_in_seconds = 1e9;
};

enum class WindowTermination { kConvergence, kNoConvergence, kFailure };

struct WindowSolverSummary {
  int iterations = 0;            // Ceres: summary.iterations.size() − 1
  int successful_steps = 0;      // Ceres: num_successful_steps (iteration 0 included)
  int unsuccessful_steps = 0;
  double initial_cost = 0.0;     // fixed cost included
  double final_cost = 0.0;
  WindowTermination termination = WindowTermination::kFailure;
  std::string message;
  double evaluation_ms = 0.0;     // costs and normal equations
  double linear_solver_ms = 0.0;  // Schur complement, Cholesky, back-substitution
  // The raw energy ‖r‖² of every photometric residual at the returned values
  // (WindowPhotometricTerms::evaluate; problem.residuals order), from the evaluation that
  // produced them: the window's outlier pass needs no evaluation of its own. Empty after a
  // failure (the starting values restored).
  std::vector<double> residual_energies;

  bool usable() const { return termination != WindowTermination::kFailure; }
};

// The normal equations at x and at the candidate (a few MB for 2000 points): kept by the
// caller from solve to solve, so that they are not allocated and first touched anew each time.
struct WindowSolverWorkspace {
  WindowNormalEquations equations, candidate_equations;
};

// Solves in place: the result is in the problem's parameter blocks. `workspace` may be null.
// With `first_estimate` (evaluateWindow) every step's photometric Jacobians are taken at the
// frames' first estimates.
WindowSolverSummary solveWindow(const WindowProblem& problem, const WindowSolverOptions& options,
                                WindowSolverWorkspace* workspace = nullptr,
                                const WindowProblem* first_estimate = nullptr);

}  // namespace omnidso
