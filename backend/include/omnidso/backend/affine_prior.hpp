#pragma once
// Gaussian prior on an affine brightness block [a, b] (eq. 5):
//   E = ½ w_a (a − ā)² + ½ w_b (b − b̄)².
// With calibrated exposure times and camera response the affine model should need no
// correction, so DSO ties [a, b] to zero with large weights; left free, (a, b) trade off
// against geometry (e.g. absorbing the contrast loss of bilinear interpolation at
// high-gradient pixels). Weight 0 leaves a parameter free (uncalibrated data).

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <cmath>

namespace omnidso {

class AffinePrior final : public ceres::SizedCostFunction<2, 2> {
 public:
  AffinePrior(const Eigen::Vector2d& mean, double weight_a, double weight_b)
      : mean_(mean), sqrt_weight_(std::sqrt(weight_a), std::sqrt(weight_b)) {}

  bool Evaluate(double const* const* x, double* r, double** J) const override {
    r[0] = sqrt_weight_[0] * (x[0][0] - mean_[0]);
    r[1] = sqrt_weight_[1] * (x[0][1] - mean_[1]);
    if (J && J[0]) {
      J[0][0] = sqrt_weight_[0];
      J[0][1] = 0.0;
      J[0][2] = 0.0;
      J[0][3] = sqrt_weight_[1];
    }
    return true;
  }

 private:
  Eigen::Vector2d mean_, sqrt_weight_;
};

}  // namespace omnidso
