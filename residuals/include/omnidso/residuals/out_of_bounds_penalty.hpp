#pragma once
// A photometric residual that, where it cannot be evaluated (its projection left the image
// or the model's domain, or its inverse distance went negative), returns a constant
// outlier-level residual with a zero Jacobian instead of failing.
//
// Why: Ceres rejects a whole trust-region step when any one residual fails to evaluate at
// the candidate point. With a thousand points, some point's pattern leaves the image for
// almost every full step, so Levenberg–Marquardt shrank its radius step after step and made
// at most one tiny move per solve. DSO instead gives an out-of-bounds residual the outlier
// energy (12² per pixel) and drops it after the solve; so do we: the penalty makes leaving
// the image cost as much as becoming an outlier — never a gain for an inlier — and the
// users (window, tracker, initialiser) leave such residuals out once the solve is done.
//
// The penalty is constant, so its zero Jacobian is exact where the wrapped residual is
// invalid; at the boundary the cost jumps, which the trust region's actual-versus-predicted
// reduction test handles like any other model mismatch.

#include <ceres/cost_function.h>
#include <ceres/problem.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "omnidso/residuals/zero_jacobians.hpp"

namespace omnidso {

class OutOfBoundsPenalty final : public ceres::CostFunction {
 public:
  // Takes ownership of `inner`; `penalty_energy` is ‖r‖² of the constant residual.
  OutOfBoundsPenalty(ceres::CostFunction* inner, double penalty_energy)
      : inner_(inner),
        penalty_(std::sqrt(penalty_energy / std::max(1, inner->num_residuals()))) {
    set_num_residuals(inner_->num_residuals());
    *mutable_parameter_block_sizes() = inner_->parameter_block_sizes();
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (inner_->Evaluate(parameters, residuals, jacobians)) return true;
    std::fill(residuals, residuals + num_residuals(), penalty_);
    zeroJacobians(*this, jacobians);
    return true;
  }

  const ceres::CostFunction& inner() const { return *inner_; }

  // ‖r‖² of the wrapped residual at `parameters` (no robust loss); +∞ where it cannot be
  // evaluated, so that any energy bound removes it.
  double rawEnergy(double const* const* parameters) const {
    constexpr int kStackResiduals = 64;  // photometric blocks have 8; no allocation for them
    std::vector<double> heap;
    double stack[kStackResiduals];
    double* r = stack;
    if (num_residuals() > kStackResiduals) {
      heap.resize(static_cast<size_t>(num_residuals()));
      r = heap.data();
    }
    if (!inner_->Evaluate(parameters, r, nullptr)) return std::numeric_limits<double>::infinity();
    return Eigen::Map<const Eigen::VectorXd>(r, num_residuals()).squaredNorm();
  }

 private:
  std::unique_ptr<ceres::CostFunction> inner_;
  double penalty_;
};

// rawEnergy of residual block `id` at the problem's current parameter values; the block's
// cost function must be an OutOfBoundsPenalty.
inline double rawEnergy(const ceres::Problem& problem, ceres::ResidualBlockId id) {
  std::vector<double*> blocks;
  problem.GetParameterBlocksForResidualBlock(id, &blocks);
  return static_cast<const OutOfBoundsPenalty&>(*problem.GetCostFunctionForResidualBlock(id))
      .rawEnergy(blocks.data());
}

}  // namespace omnidso
