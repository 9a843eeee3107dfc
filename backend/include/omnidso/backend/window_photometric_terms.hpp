#pragma once
// The window's photometric residuals for the native solver (window_solver.hpp): the cost
// ½ρ(‖r‖²) of every (point, target) residual of eq. 5–7, and on request their contribution
// to the normal equations (window_normal_equations.hpp), from the per-pixel kernel the
// Ceres cost function uses (residuals/photometric_kernel.hpp) — so both minimise the same
// function — with the Jacobians written in the tangent space directly.
//
// Relative-pose form (as DSO accumulates): a residual depends on the two poses only
// through T_th = T_target_host. With ε a left perturbation of it, T_th ← exp(ε) T_th,
//   ∂x̃/∂ε = [d I, −[x̃]×]                              (x̃ = R b + d t, ε = [ρ; φ])
//   host:   T_wh ← T_wh exp(δ_h)  ⇒ ε = Ad(T_th) δ_h,  Ad(T) = [[R, [t]× R], [0, R]]
//   target: T_wt ← T_wt exp(δ_t)  ⇒ ε = −δ_t
// (J_ε Ad = [d gR, −gR[b]×] and −J_ε = [−d g, g[x̃]×]: photometric_analytic.hpp's rows).
// Affine, with α_o = √w s h_o, γ_o = −√w (and β_o = √w s = −s γ_o): ∂r/∂[a_i b_i] =
// [α −sγ], ∂r/∂[a_j b_j] = [−α γ]. So per residual the Jacobian has the pair columns
// [J_ε α γ], the intrinsics (K, level 0) and the inverse distance; per pair their JᵀJ (and
// Jᵀr) are summed, and mapped to the two frames' [pose affine] blocks once per pair:
//   [J_host J_target] = J_pair · [M_h M_t],  M_h = [[Ad, 0], [0, e_a], [0, −s e_b]],
//   M_t = [[−I, 0], [0, −e_a], [0, e_b]].
// Per point: h_p, g_p, and its row of W (the coupling to the frames) per residual.
//
// Robust loss: Ceres's correction on the block (robust_correction.hpp). Invalid residuals
// (out of the image, the model's domain, d < 0) carry OutOfBoundsPenalty's constant outlier
// energy and a zero Jacobian.
//
// Host bearings b_o and ∂b_o/∂c are computed once per point and reused while the problem
// (WindowProblem::id) and the intrinsics do not change (every evaluation of a solve with
// constant intrinsics; an evaluation and the linearisation after an accepted step
// otherwise). Nothing is allocated per residual, and the buffers are kept between calls.
// Summation order: per pair, its residuals in problem order; per point and for the cost, the
// residuals in problem order (points by id, targets by keyframe id); the pairs mapped to the
// frames by (host, target) index. The residuals are evaluated pair by pair on the problem's
// compute threads; the sums do not depend on them (window_photometric_terms.cc).

#include <vector>
#include <memory>
#include <omnidso/backend/window_problem.hpp>

namespace omnidso {

class WindowNormalEquations;

class WindowPhotometricTerms {
 public:
  virtual ~WindowPhotometricTerms() = default;
  // Σ ½ρ(‖r‖²) over problem.residuals at the values in the blocks. With `equations`, also
  // adds each residual's J̃ᵀJ̃ and J̃ᵀr̃ (robust-corrected) into them; with `energies`, sets
  // each residual's raw energy ‖r‖² (no robust loss; +∞ where it is invalid, as
  // OutOfBoundsPenalty::rawEnergy), in problem.residuals order.
  virtual double evaluate(const WindowProblem& problem, WindowNormalEquations* equations,
                          std::vector<double>* energies = nullptr) = 0;
  // The marginalisation's linearisation (marginalizer.hpp, step 2, with first-estimate
  // Jacobians): into `equations`, every residual's J̃ᵀJ̃ and J̃ᵀr̃ with r̃ at the values of
  // `current` and J̃ at those of `first_estimate` — two problems with the same points and
  // residuals whose frames and intrinsics point to different values. `gradient_at` says where
  // J̃ takes the image gradient ∇I_j:
  //  - kCurrentEstimate (DSO, Engel et al. 2018, sec. 2.3; the solver and the marginalisation):
  //    the geometric factors ∂π/∂x̃ ∂x̃/∂ξ at `first_estimate`, ∇I_j and the robust weight at
  //    `current`, where the residual is — the image is not smooth on the scale of how far a
  //    projection moves between the two. A residual invalid at either adds nothing.
  //  - kFirstEstimate: the whole Jacobian and its robust weight at `first_estimate`, as Ceres
  //    evaluates a residual block there (the tests' oracle). A residual invalid at
  //    `first_estimate` adds nothing; one invalid at `current` has OutOfBoundsPenalty's
  //    residual there.
  enum class ImageGradientAt { kCurrentEstimate, kFirstEstimate };
  virtual void linearizeAt(const WindowProblem& current, const WindowProblem& first_estimate,
                           WindowNormalEquations* equations,
                           ImageGradientAt gradient_at = ImageGradientAt::kCurrentEstimate) = 0;
  // evaluate() at `current` — the cost and `energies` — with the normal equations of
  // linearizeAt(current, first_estimate): the window's solve with first-estimate Jacobians
  // (WindowOptions::first_estimate_jacobians).
  virtual double evaluateAt(const WindowProblem& current, const WindowProblem& first_estimate,
                            WindowNormalEquations* equations,
                            std::vector<double>* energies = nullptr) = 0;
};

// One instantiation per camera model with a residual kernel (photometric_factory.hpp).
template <template <typename> class Camera>
std::unique_ptr<WindowPhotometricTerms> makeWindowPhotometricTerms();

}  // namespace omnidso
