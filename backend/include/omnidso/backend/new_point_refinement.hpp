#pragma once
// Refinement of a candidate point against every window keyframe before it is activated
// (DSO Sec. 3.2, "candidate point activation": each candidate is optimised against all
// keyframes of the window before it enters the joint optimisation).
//
// Why: the epipolar search gives a point's inverse distance from ONE frame — the latest in
// which it was traced — and in low-parallax, rotation-heavy stretches that interval is wide
// (the midpoint may be off by a factor of two). Activated with such a depth, the point enters
// the window's 2-iteration solve far from its minimum and pulls the poses, and with them the
// scale, towards its wrong depth. Here, with every pose, affine block and the intrinsics held
// at the window's estimate, the point's photometric energy over all its targets,
//   E(d) = Σ_k ρ(‖r_k(d)‖²)      (r_k: the window's own residual of eq. 5–7 into keyframe k,
//                                 ρ: the window's Huber loss),
// is minimised over d alone by Levenberg–Marquardt on the Gauss–Newton model
//   H = Σ_k ρ'_k J_kᵀ J_k,  g = Σ_k ρ'_k J_kᵀ r_k,  δ = −g / (H (1 + λ)),   J_k = ∂r_k/∂d.
// The point is accepted when
//   - H ≥ min_hessian: the window's keyframes observe its inverse distance (σ_d = H^{-1/2}
//     in units of the residual's intensity noise); otherwise it stays a candidate and may be
//     activated later, once the baseline has grown;
//   - at least min_good_residuals targets have a raw energy below the window's outlier bound;
//   - d stays positive and finite.
// A point with enough information but too few good targets is inconsistent with the window
// (a wrong match of the epipolar search): the caller drops it.

#include <Eigen/Core>

namespace omnidso {

struct NewPointRefinementOptions {
  bool enabled = true;
  int iterations = 3;
  // Information on the inverse distance, Σ ρ' (∂r/∂d)², in (intensity / inverse distance)²
  // with the odometry's scale (mean inverse distance 1 at initialisation).
  double min_hessian = 100.0;
  int min_good_residuals = 1;
  // The image gradient in the refinement's Jacobians (ImageGradient, photometric_residual.hpp):
  // false, the bilinear interpolant's derivative; true, DSO's central differences. Off: with the
  // window's solve on central differences too, two of H12p's six seeds read 0.13 / 0.30 %
  // against none above 0.075 % with the solve alone (docs/performance.md, "The image gradient
  // in the Jacobians").
  bool central_difference_gradients = false;
};

enum class NewPointVerdict {
  kAccepted,
  kUnobserved,    // too little information on d: keep it as a candidate
  kInconsistent,  // observed, but too few good residuals (or d left (0, ∞)): drop it
};

struct NewPointRefinement {
  NewPointVerdict verdict = NewPointVerdict::kUnobserved;
  double inverse_distance = 0.0;
  double hessian = 0.0;
  int num_good_residuals = 0;
  int num_targets = 0;
};

}  // namespace omnidso
