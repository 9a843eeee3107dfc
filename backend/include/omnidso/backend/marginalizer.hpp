#pragma once
// Marginalisation with the Schur complement, on Ceres's own linearisation (paper
// Sec. V-D; DSO Sec. 2.3).
//
// marginalize(problem, M) removes the parameter blocks M from `problem`:
//  1. R = every residual block connected to a block of M (old priors included, so priors
//     accumulate); K = the other non-constant blocks those residuals touch.
//  2. Linearise R block by block with Problem::EvaluateResidualBlock (loss functions and
//     manifolds applied, so J is in tangent coordinates): residuals r at the current
//     estimate, Jacobians J at the first-estimate point x̄ of every block (the stored one
//     for blocks already under a prior, the current value otherwise). In δ = x ⊟ x̄
//     coordinates
//        r(δ) ≈ r₀ + J δ,   r₀ = r(x) − J (x ⊟ x̄).
//  3. H = JᵀJ, g = Jᵀr₀, ordered [M | K], summed residual block by residual block (no
//     global J is formed); Schur complement
//        H* = H_KK − H_KM H_MM⁺ H_MK,   g* = g_K − H_KM H_MM⁺ g_M
//     (H_MM⁺ a pseudo-inverse: a marginalised block may carry no information).
//  4. Factor H* = V Λ Vᵀ, keep λ > ε λ_max, S = Λ^½ Vᵀ, s = Λ^-½ Vᵀ g*, so that
//     ½‖S δ_K + s‖² = ½ δ_Kᵀ H* δ_K + g*ᵀ δ_K + const — the prior (marginalization_prior.hpp).
//  5. Remove R and M from the problem, add the prior on K, and record x̄ for the blocks
//     of K that had none, so that later priors linearise them at the same point.
// If the evaluation at x̄ fails (e.g. a projection leaves the image there), the Jacobians of
// the current estimate are used instead, still expressed about x̄.

#include <ceres/problem.h>

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

namespace omnidso {

struct MarginalizationOptions {
  // Relative eigenvalue threshold below which a direction of H* carries no information.
  double eigenvalue_threshold = 1e-12;
};

struct MarginalizationStats {
  int num_residual_blocks = 0;
  int num_marginalized_blocks = 0;
  int num_prior_blocks = 0;  // blocks the new prior connects
  int prior_rank = 0;
  bool used_first_estimate_jacobians = true;
  int num_unevaluable_residual_blocks = 0;  // left out: not evaluable at the current estimate
};

class Marginalizer {
 public:
  explicit Marginalizer(MarginalizationOptions options = {}) : options_(options) {}

  // Returns the residual block of the new prior, or nullptr when no information remains.
  ceres::ResidualBlockId marginalize(ceres::Problem& problem, const std::vector<double*>& blocks,
                                     MarginalizationStats* stats = nullptr);

  // Steps 4–5 for a Schur complement formed elsewhere (the window's native marginalisation
  // of points, window_point_marginalization.hpp): H* and g* over `kept` — non-constant blocks
  // of `problem`, in δ = x ⊟ x̄ coordinates with x̄ each block's firstEstimate — become a
  // prior in `problem`. Returns its residual block, or nullptr when H* carries no information.
  ceres::ResidualBlockId addPrior(ceres::Problem& problem, const std::vector<double*>& kept,
                                  const Eigen::MatrixXd& H_star, const Eigen::VectorXd& g_star,
                                  MarginalizationStats* stats = nullptr);

  // x̄ of a block: its first-estimate point, or its current value when no prior touches it.
  Eigen::VectorXd firstEstimate(const ceres::Problem& problem, const double* block) const;
  // First-estimate point of a block, or nullptr when no prior touches it.
  const Eigen::VectorXd* linearizationPoint(const double* block) const;
  // Call when a block leaves the problem by other means (e.g. a dropped point).
  void forget(const double* block) { linearization_points_.erase(block); }

 private:
  MarginalizationOptions options_;
  std::unordered_map<const double*, Eigen::VectorXd> linearization_points_;
};

}  // namespace omnidso
