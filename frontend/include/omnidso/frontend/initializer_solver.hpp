#pragma once
// The initialiser's native level solve: Levenberg–Marquardt for one pyramid level of the
// two-frame initialiser (initializer.hpp) over the frame's pose T (T ⊞ δ = T exp(δ), δ ∈ ℝ⁶,
// se3_manifold.hpp), its affine brightness [a, b] and one inverse distance d_p per point,
// minimising (eq. 5–7, with the initialiser's regularisers)
//   E = Σ_p [ ½ ρ(‖r_p(T, a, b, d_p)‖²) + ½ λ (d_p − d̄)² ] + ½ λN ‖t‖² + ½ w_a a² + ½ w_b b²,
// r_p the 8-pixel photometric patch of point p, ρ Huber's loss of threshold k√8
// (makePhotometricLoss), the translation term only before the snap (r_t = √(λN) t, t the
// frame's position, pose parameters 4–6), the prior that of backend/affine_prior.hpp.
// Why: the Ceres path builds a ceres::Problem per frame, level and rotation hypothesis, and
// its per-block plumbing (ambient Jacobians through the manifold, dynamic-size blocks, the
// generic Schur eliminator, a Program per Problem::Evaluate) was most of the initialiser's
// ≈ 2 s per segment start (docs/performance.md, "The initialiser's native solve").
//
// Every patch touches only its own d_p and the frame's 8 parameters x_f = [δ a b], so with
//   H_ff = Σ J̃_fᵀJ̃_f (8×8),  h_p = ‖J̃_d‖² + λ,  w_p = J̃_dᵀJ̃_f (1×8),
//   g_f = Σ J̃_fᵀr̃,  g_p = J̃_dᵀr̃ + √λ r_reg
// (J̃, r̃ after Ceres's robust correction, backend/robust_correction.hpp) the d_p are
// eliminated by the Schur complement and the reduced system is 8×8. It reproduces
// ceres::Solve with the initialiser's options (Ceres 2.1: LEVENBERG_MARQUARDT, DENSE_SCHUR
// with the inverse distances in the first elimination group, Jacobi scaling — Ceres's
// default —, monotonic steps), so the two differ only by rounding:
//  - Jacobi scaling of every column (points included) from iteration 0's Jacobian,
//    s_j = 1 / (1 + ‖J̃_j‖), kept; in the scaled space H̃ = SHS, g̃ = Sg (with D² ∝ diag H̃
//    the scaling cancels except in the clamp and the rounding, as tracker_solver.hpp notes;
//    it is kept to follow Ceres's arithmetic);
//  - the step: D² = clamp(diag H̃) / Δ (trust_region.hpp) for the frame and the points;
//    with A_p = h̃_p + D_p² (the damped eliminated block, as Ceres's SchurEliminator adds D
//    to EᵀE before inverting it)
//      (H̃_ff + D_f² − Σ_p w̃_pᵀw̃_p / A_p) y_f = g̃_f − Σ_p w̃_pᵀ g̃_p / A_p   (8×8 Cholesky)
//      y_p = (g̃_p − w̃_p y_f) / A_p,   δ = −S y;
//  - the model cost change L = −δᵀg − ½ δᵀHδ with
//    δᵀHδ = δ_fᵀH_ffδ_f + Σ_p (2 δ_p w_p δ_f + h_p δ_p²); invalid when the factorisation
//    fails, δ is not finite or L ≤ 0;
//  - the rest as tracker_solver.hpp lists it: patches invalid at the start are left out,
//    one that becomes invalid counts as OutOfBoundsPenalty's constant through the loss with
//    a zero Jacobian; ε_p on every ambient number (pose 7, affine 2, the d_p) with ‖x‖ = −1
//    before the first accepted step, |ΔE| ≤ ε_f E, ‖x − (x ⊞ −g)‖_∞ ≤ ε_g, Δ ≤ 1e-32,
//    acceptance at ρ > 1e-3, five invalid steps a failure that leaves the start in place;
//    the final cost the least iteration cost.
// Deterministic, single-threaded; points summed in order.

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <omnidso/backend/trust_region.hpp>
#include <vector>

namespace ceres {
class LossFunction;
}

namespace omnidso {

// The photometric patches of one level (one per point), evaluated at one frame state.
class InitializerPatches {
 public:
  static constexpr int kPatchSize = 8;
  using Residuals = Eigen::Matrix<double, kPatchSize, 1>;
  using FrameJacobian = Eigen::Matrix<double, kPatchSize, 8, Eigen::RowMajor>;  // ∂r/∂[δ a b]

  virtual ~InitializerPatches() = default;
  // An independent copy (the same patches, its own frame state): one per thread, so that
  // several states can be evaluated at once.
  virtual std::unique_ptr<InitializerPatches> clone() const = 0;
  virtual int size() const = 0;
  // The frame state evaluate() works at: pose [qx qy qz qw tx ty tz], affine [a b].
  virtual void setPoint(const double* pose, const double* affine) = 0;
  // r of patch i at inverse distance d and, when the Jacobians are not null, ∂r/∂[δ a b]
  // and ∂r/∂d. False where the patch cannot be evaluated (out of the image or the model's
  // domain, d < 0).
  virtual bool evaluate(int i, double inverse_distance, Residuals* r, FrameJacobian* J_frame,
                        Residuals* J_d) const = 0;
};

struct InitializerLevelProblem {
  InitializerPatches* patches = nullptr;
  const ceres::LossFunction* loss = nullptr;   // of each patch (makePhotometricLoss)
  double invalid_residual = 0.0;               // per pixel, OutOfBoundsPenalty's constant
  double regularizer_sqrt_weight = 0.0;        // √λ
  double regularizer_mean = 1.0;               // d̄
  double translation_sqrt_weight = 0.0;        // √(λN); 0: no translation term
  double affine_prior_weight_a = 0.0;          // about [0, 0]; both 0: no prior
  double affine_prior_weight_b = 0.0;
};

struct InitializerSolverOptions : LevenbergMarquardtOptions {  // Ceres's names and defaults
  bool jacobi_scaling = true;
};

enum class InitializerTermination { kConvergence, kNoConvergence, kFailure };

struct InitializerSolverSummary {
  int iterations = 0;          // Ceres: summary.iterations.size() − 1
  int successful_steps = 0;    // Ceres: num_successful_steps (iteration 0 included)
  int unsuccessful_steps = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  InitializerTermination termination = InitializerTermination::kFailure;
  // ‖r_p‖² of every patch at the returned values — the start after a failure — (no loss;
  // +∞ where invalid), from the evaluation there: OutOfBoundsPenalty::rawEnergy of the
  // Ceres path.
  std::vector<double> energies;
};

// Solves in place: pose (7), affine (2) and the patches' inverse distances hold the start
// and receive the result (left untouched by a failure, as by Ceres).
InitializerSolverSummary solveInitializerLevel(const InitializerLevelProblem& problem,
                                               const InitializerSolverOptions& options,
                                               double* pose, double* affine,
                                               std::vector<double>* inverse_distances);

// E at the given values (Problem::Evaluate's cost, to rounding); +∞ where a residual is
// not finite (where Problem::Evaluate fails). With a finite `bound`, +∞ as soon as the sum
// exceeds it: every term is ≥ 0, so the partial sums only grow, and a cost ≤ bound is
// returned exactly as without one (a search for the least cost loses nothing by it).
double initializerLevelCost(const InitializerLevelProblem& problem, const double* pose,
                            const double* affine, const std::vector<double>& inverse_distances,
                            double bound = std::numeric_limits<double>::infinity());

}  // namespace omnidso
