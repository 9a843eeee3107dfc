#pragma once
// The robust loss of a residual block as Ceres applies it (Triggs et al., "Bundle
// Adjustment — A Modern Synthesis", Sec. 4.3, eq. 11; Ceres's Corrector, corrector.cc):
// with s = ‖r‖² and ρ(s), ρ′, ρ″ from the loss,
//   cost = ½ ρ(s)
//   r̃ = √ρ′ / (1 − α) · r,   J̃ = √ρ′ (J − (α/s) r rᵀ J),   α = 1 − √(1 + 2 s ρ″/ρ′),
// so that J̃ᵀJ̃ and J̃ᵀr̃ are the Gauss–Newton model of ½ρ. Where ρ″ ≤ 0 (Huber's outer part)
// or s = 0 Ceres drops the curvature term (α = 0): r and J are scaled by √ρ′ only.
// Without a loss, cost = ½ s and nothing is scaled.

#include <ceres/loss_function.h>

#include <Eigen/Core>
#include <cmath>

namespace omnidso {

class RobustCorrection {
 public:
  // `loss` may be nullptr; `squared_norm` = ‖r‖².
  RobustCorrection(const ceres::LossFunction* loss, double squared_norm) {
    if (!loss) {
      cost_ = 0.5 * squared_norm;
      return;
    }
    double rho[3];
    loss->Evaluate(squared_norm, rho);
    cost_ = 0.5 * rho[0];
    sqrt_rho1_ = std::sqrt(rho[1]);
    residual_scaling_ = sqrt_rho1_;
    if (squared_norm == 0.0 || rho[2] <= 0.0) return;
    const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * squared_norm * rho[2] / rho[1]);
    residual_scaling_ = sqrt_rho1_ / (1.0 - alpha);
    alpha_over_squared_norm_ = alpha / squared_norm;
  }

  double cost() const { return cost_; }

  // J̃ from J (rows: residuals) and the uncorrected r; then r̃ from r. Call in this order.
  template <typename Jacobian, typename Residuals>
  void correctJacobian(const Residuals& r, Eigen::MatrixBase<Jacobian>& J) const {
    if (alpha_over_squared_norm_ == 0.0) {
      if (sqrt_rho1_ != 1.0) J *= sqrt_rho1_;
      return;
    }
    for (int c = 0; c < J.cols(); ++c) {
      const double r_transpose_j = r.dot(J.col(c));
      J.col(c) = sqrt_rho1_ * (J.col(c) - (alpha_over_squared_norm_ * r_transpose_j) * r);
    }
  }
  template <typename Residuals>
  void correctResiduals(Eigen::MatrixBase<Residuals>& r) const {
    if (residual_scaling_ != 1.0) r *= residual_scaling_;
  }

 private:
  double cost_ = 0.0;
  double sqrt_rho1_ = 1.0;
  double residual_scaling_ = 1.0;
  double alpha_over_squared_norm_ = 0.0;
};

}  // namespace omnidso
