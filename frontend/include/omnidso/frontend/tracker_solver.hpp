#pragma once
// The native tracker solver: Levenberg–Marquardt for one pyramid level of the coarse tracker
// (coarse_tracker.hpp) over the relative pose T (T ⊞ δ = T exp(δ), δ ∈ ℝ⁶, se3_manifold.hpp)
// and the frame's affine brightness [a, b], minimising (eq. 5)
//   E(T, a, b) = Σ_i ½ ρ(r_i(T, a, b)²) + ½ w_a (a − ā)² + ½ w_b (b − b̄)²,
// ρ Huber's loss of threshold k, the prior that of backend/affine_prior.hpp.
// Why: ceres::Solve builds a Problem per frame, level and hypothesis and evaluates each
// one-pixel residual through its per-block plumbing (ambient Jacobians, manifold products,
// a dynamic-size Jacobian, allocations); for an 8-dimensional problem that plumbing was most
// of the ≈ 11 ms of tracking per frame. Here the 8×8 normal equations are summed directly
// from each residual's value and tangent Jacobian (tracking_residual.hpp,
// evaluateTrackingResidual).
//
// It reproduces ceres::Solve with the tracker's options (Ceres 2.1: LEVENBERG_MARQUARDT,
// DENSE_NORMAL_CHOLESKY, Jacobi scaling, monotonic steps; trust_region_minimizer.cc,
// levenberg_marquardt_strategy.cc), so the two differ only by rounding in the step:
//  - the cost, bit for bit, and the robust correction of Ceres's Corrector
//    (backend/robust_correction.hpp): Huber's ρ″ is never positive, so r and J are scaled by
//    √ρ′ (1 inside the threshold); the prior has no loss;
//  - a residual that cannot be evaluated at the start is left out; one that cannot at a
//    later point counts as the constant `invalid_residual` with a zero Jacobian
//    (residuals/out_of_bounds_penalty.hpp); a non-finite residual or Jacobian fails the
//    evaluation, as in Ceres (at a candidate: cost +∞, the step is rejected);
//  - Jacobi scaling (Ceres's default): the columns of J̃ are scaled by
//    s_j = 1 / (1 + ‖J̃_j‖), s taken at iteration 0 and kept; so with S = diag(s),
//    H = J̃ᵀJ̃ and g = J̃ᵀr̃ the step solves (SHS + D²) y = S g, D² = clamp(diag SHS) / Δ
//    (trust_region.hpp), by an 8×8 Cholesky, and δ = −S y. (With Marquardt's D² ∝ diag H
//    the scaling cancels — S(H + diag H/Δ)S = SHS + diag(SHS)/Δ — except in the clamp and
//    in the rounding; it is kept to follow Ceres's arithmetic.)
//  - the model cost change L = −δᵀg − ½ δᵀHδ (Ceres: −(J̃δ)ᵀ(r̃ + J̃δ/2)); the step is
//    invalid when the factorisation fails, δ is not finite or L ≤ 0;
//  - the candidate, the tolerances, acceptance (ρ = ΔE / L > 1e-3) and the trust-region
//    update as window_solver.hpp lists them: ε_p on the 9 ambient numbers with ‖x‖ = −1
//    before the first accepted step, |ΔE| ≤ ε_f E, ‖x − (x ⊞ −g)‖_∞ ≤ ε_g with the unscaled
//    gradient (after accepted steps), Δ ≤ 1e-32, five invalid steps in a row a failure
//    that restores the start (as Ceres leaves the user's values untouched);
//  - the final cost is the least iteration cost (Ceres's SetSummaryFinalCost).
// No time limit (Ceres's default, 10⁹ s, never ends a level). Deterministic, single-threaded,
// no allocation per iteration.

#include <Eigen/Core>
#include <omnidso/backend/trust_region.hpp>

namespace omnidso {

// The residuals r_i(T, a, b) of one level, evaluated at one point at a time.
class TrackerResiduals {
 public:
  virtual ~TrackerResiduals() = default;
  virtual int size() const = 0;
  // The point at which evaluate() works: pose [qx qy qz qw tx ty tz], affine [a b].
  virtual void setPoint(const double* pose, const double* affine) = 0;
  // r_i and, if `jacobian` is not null, ∂r_i/∂[δ a b] (8 numbers, δ of T ⊞ δ). False where
  // r_i cannot be evaluated (outside the image, behind the camera).
  virtual bool evaluate(int i, double* residual, double* jacobian) const = 0;
};

struct TrackerProblem {
  TrackerResiduals* residuals = nullptr;
  double huber_threshold = 9.0;  // k
  double invalid_residual = 0.0;  // r of a residual that became invalid (√ of its energy)
  // The affine prior; left out when both weights are 0 (as the tracker leaves out Ceres's).
  Eigen::Vector2d affine_prior_mean = Eigen::Vector2d::Zero();  // [ā, b̄]
  double affine_prior_weight_a = 0.0;
  double affine_prior_weight_b = 0.0;
  // With fewer residuals valid at the start nothing is solved (the tracker's 8: the unknowns).
  int min_residuals = 8;
};

struct TrackerSolverOptions : LevenbergMarquardtOptions {  // Ceres's names and defaults
  bool jacobi_scaling = true;
};

enum class TrackerTermination { kNotSolved, kConvergence, kNoConvergence, kFailure };

struct TrackerSolverSummary {
  int num_residuals = 0;       // valid at the start: the residuals solved over
  int iterations = 0;          // Ceres: summary.iterations.size() − 1
  int successful_steps = 0;    // Ceres: num_successful_steps (iteration 0 included)
  int unsuccessful_steps = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  TrackerTermination termination = TrackerTermination::kNotSolved;
};

// Solves in place: pose (7) and affine (2) hold the start and receive the result.
TrackerSolverSummary solveTracker(const TrackerProblem& problem,
                                  const TrackerSolverOptions& options, double* pose,
                                  double* affine);

}  // namespace omnidso
