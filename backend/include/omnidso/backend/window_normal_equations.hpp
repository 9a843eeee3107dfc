#pragma once
// The window's Gauss–Newton normal equations in tangent coordinates (window_problem.hpp),
// and the Levenberg–Marquardt step with the points eliminated, as Ceres's
// LevenbergMarquardtStrategy computes it with DENSE_SCHUR.
//
// Stored, with J̃ and r̃ Ceres's robust-corrected Jacobian and residuals of every residual
// block (window_objective.hpp):
//   H_ff = J̃_fᵀ J̃_f  (frame space, dense and symmetric),      g_f = J̃_fᵀ r̃
//   per point p:  h_p = J̃_pᵀ J̃_p,  g_p = J̃_pᵀ r̃,  w_p = J̃_pᵀ J̃_f  (row p of W, frame space)
// H_pp is diagonal because every residual observes exactly one point.
//
// The step at trust-region radius Δ (Ceres: D² = clamp(diag(JᵀJ), min, max) / Δ, solve
// (JᵀJ + D²) y = Jᵀr, step = −y), over the variable coordinates only:
//   S   = H_ff + D_f² − Σ_p w_pᵀ w_p / (h_p + D_p²)     the reduced camera system
//   S y_f = g_f − Σ_p w_pᵀ g_p / (h_p + D_p²)          dense Cholesky (DENSE_SCHUR's)
//   y_p = (g_p − w_p y_f) / (h_p + D_p²)                back-substitution
// A failed factorisation is Ceres's LINEAR_SOLVER_FAILURE: the step is invalid.
// Model cost change (Ceres: −(J̃ δ)ᵀ(r̃ + J̃ δ / 2)) = −δᵀg − ½ δᵀ(JᵀJ)δ, with
//   δᵀ(JᵀJ)δ = δ_fᵀ H_ff δ_f + 2 Σ_p δ_p w_p δ_f + Σ_p h_p δ_p².
// The points' Schur terms are summed in point order by one rank update (Σ_p ŵ_pᵀ ŵ_p with
// ŵ_p = w_p / √(h_p + D_p²)), so the result does not depend on memory addresses.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <omnidso/backend/trust_region.hpp>
#include <vector>

namespace omnidso {

// Which coordinates the linear system solves for (constant blocks are left out).
struct WindowVariables {
  std::vector<int> frame_columns;   // variable frame-space coordinates, ascending
  std::vector<char> point_variable;  // per point
};

class WindowNormalEquations {
 public:
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  // Zero equations for a frame space of `frame_space_size` coordinates and `num_points`.
  void reset(int frame_space_size, int num_points);

  // Exchanges the equations with `other` (the solver's x and candidate): O(1), the storage
  // changes hands. The Cholesky workspace stays: a default-constructed Eigen::LLT holds an
  // uninitialised status, so moving it (std::swap) reads an indeterminate value, which
  // UBSan reports; compute() rebuilds it on every step anyway.
  void swap(WindowNormalEquations& other) noexcept;

  int frameSpaceSize() const { return static_cast<int>(g_f_.size()); }
  int numPoints() const { return static_cast<int>(h_p_.size()); }

  // Accumulation (window_objective.cc, window_photometric_terms.cc).
  Eigen::MatrixXd& frameHessian() { return H_ff_; }
  Eigen::VectorXd& frameGradient() { return g_f_; }
  double& pointHessian(int p) { return h_p_[p]; }
  double& pointGradient(int p) { return g_p_[p]; }
  auto pointCoupling(int p) { return W_.row(p); }

  const Eigen::MatrixXd& frameHessian() const { return H_ff_; }
  const Eigen::VectorXd& frameGradient() const { return g_f_; }
  const Eigen::VectorXd& pointHessian() const { return h_p_; }
  const Eigen::VectorXd& pointGradient() const { return g_p_; }
  const RowMatrix& pointCoupling() const { return W_; }

  // S (lower triangle) and its right-hand side over variables.frame_columns.
  void reducedCameraSystem(const WindowVariables& variables,
                           const LevenbergMarquardtDamping& damping, Eigen::MatrixXd* lhs,
                           Eigen::VectorXd* rhs) const;

  // The step δ = −y (frame space and per point; zero at constant coordinates). False when
  // the Cholesky factorisation fails or the step is not finite.
  bool solveStep(const WindowVariables& variables, const LevenbergMarquardtDamping& damping,
                 Eigen::VectorXd* frame_step, Eigen::VectorXd* point_step);

  // −δᵀg − ½ δᵀ(JᵀJ)δ.
  double modelCostChange(const Eigen::VectorXd& frame_step,
                         const Eigen::VectorXd& point_step) const;

 private:
  double dampedPointHessian(int p, const LevenbergMarquardtDamping& damping) const;

  Eigen::MatrixXd H_ff_;
  Eigen::VectorXd g_f_;
  Eigen::VectorXd h_p_, g_p_;
  RowMatrix W_;
  // Workspace of solveStep and reducedCameraSystem, kept between steps (a fresh ŵ matrix
  // per step was a megabyte of page faults each time).
  Eigen::MatrixXd lhs_;
  Eigen::VectorXd rhs_;
  mutable RowMatrix scaled_coupling_;
  mutable Eigen::VectorXd scaled_gradient_;
  Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> cholesky_;
};

}  // namespace omnidso
