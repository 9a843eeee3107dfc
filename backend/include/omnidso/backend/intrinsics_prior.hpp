#pragma once
// Gaussian prior tying the camera intrinsics [fx fy cx cy extra…] to the calibration θ⁰:
//   E = ½ w Σ_i (s_i (θ_i − θ⁰_i))²,   s_i = 1 for fx, fy, cx, cy;  s_i = f̄ = (fx⁰ + fy⁰)/2
//                                        for the model's dimensionless parameters (ξ, α, β, k…),
// so that w is an energy per squared pixel of image displacement throughout (a unit change
// of ξ, α or k moves the image periphery by about f̄ pixels). Why: the window's photometric
// energy observes some intrinsic combinations only weakly — with small or one-axis rotation a
// principal-point shift acts almost as one rotation of every camera (see the window tests) —
// and, left free, they wander and take the map's scale with them. DSO holds its calibration
// with such a prior too. w = 0 leaves the intrinsics free.

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <cmath>

namespace omnidso {

class IntrinsicsPrior final : public ceres::CostFunction {
 public:
  IntrinsicsPrior(const Eigen::VectorXd& calibration, double weight)
      : mean_(calibration), sqrt_weight_scale_(calibration.size()) {
    const double mean_focal = 0.5 * (calibration[0] + calibration[1]);
    for (int i = 0; i < calibration.size(); ++i)
      sqrt_weight_scale_[i] = std::sqrt(weight) * (i < 4 ? 1.0 : mean_focal);
    set_num_residuals(static_cast<int>(calibration.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(calibration.size()));
  }

  bool Evaluate(double const* const* x, double* r, double** J) const override {
    const int n = static_cast<int>(mean_.size());
    for (int i = 0; i < n; ++i) r[i] = sqrt_weight_scale_[i] * (x[0][i] - mean_[i]);
    if (J && J[0]) {
      Eigen::Map<Eigen::MatrixXd> jacobian(J[0], n, n);  // row-major = column-major: diagonal
      jacobian.setZero();
      jacobian.diagonal() = sqrt_weight_scale_;
    }
    return true;
  }

 private:
  Eigen::VectorXd mean_, sqrt_weight_scale_;
};

}  // namespace omnidso
