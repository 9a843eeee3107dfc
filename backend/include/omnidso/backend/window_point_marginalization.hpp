#pragma once
// Marginalisation of window points from the native solver's photometric terms
// (window_photometric_terms.hpp): the Schur complement that Marginalizer::marginalize forms
// through Ceres for the same points (marginalizer.hpp, steps 1–3), with no residual block in
// the ceres::Problem. Adding, evaluating and removing those blocks through Ceres was as much
// of a keyframe's mapping time as the window solve (docs/performance.md, "Native point
// marginalisation; one point per coarse pixel in the initialiser").
//
// For the points of `current` — all their residuals and only those; no prior touches a
// point — with x̄ the first-estimate point of the frames' and the intrinsics' blocks
// (`first_estimate`: the same problem with those blocks' values at x̄; the points at x):
//   per residual   J̃ at x̄ (the image gradient at x: window_photometric_terms.hpp), r̃ at x,
//                  r₀ = r̃ − J̃ (x ⊟ x̄)
//   H = Σ J̃ᵀJ̃,    g = Σ J̃ᵀ r₀ = Σ J̃ᵀ r̃ − H (x ⊟ x̄)
//   H* = H_KK − Σ_p w_pᵀ w_p / h_p,   g* = g_K − Σ_p w_pᵀ g_p / h_p
// with K the variable frame and intrinsics blocks that some residual touches, and p over the
// variable points with h_p > 0 (H_MM is diagonal: every residual observes one point, and the
// pseudo-inverse of a 1×1 block is 1/h_p or 0). Constant blocks are known, as in
// Marginalizer: no column, no δ. ⊟ is the blocks' manifold Minus (the problem's
// pose_manifold for poses), the tangent of the native Jacobians.

#include <Eigen/Core>
#include <omnidso/backend/window_photometric_terms.hpp>
#include <omnidso/backend/window_problem.hpp>
#include <vector>

namespace omnidso {

struct PointSchurComplement {
  // K: the frames' pose and affine blocks, oldest frame first, then the intrinsics.
  std::vector<double*> blocks;
  Eigen::MatrixXd information;  // H*, in the blocks' tangent coordinates side by side
  Eigen::VectorXd gradient;     // g*
};

// `gradient_at`: WindowPhotometricTerms::linearizeAt's (the image gradient at the current
// estimate, as DSO; kFirstEstimate is Ceres's linearisation, the tests' oracle).
PointSchurComplement marginalizePoints(
    const WindowProblem& current, const WindowProblem& first_estimate,
    WindowPhotometricTerms::ImageGradientAt gradient_at =
        WindowPhotometricTerms::ImageGradientAt::kCurrentEstimate);

}  // namespace omnidso
