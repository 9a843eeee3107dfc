#pragma once
// The Gaussian prior left behind by marginalisation, in square-root information form:
//
//   E_prior(x) = ½ ‖ S·δ(x) + s ‖²,   δ(x) = [x_1 ⊟ x̄_1; …; x_n ⊟ x̄_n],
//
// where x̄_k is the linearisation point of block k (kept fixed for the life of the prior:
// first-estimate Jacobians) and ⊟ is the block's manifold Minus (plain subtraction for
// Euclidean blocks). SᵀS is the Schur-complement information H* and Sᵀs the reduced
// gradient g* (see marginalizer.hpp).
//
// Jacobians: the prior is linear in δ, so its tangent-space Jacobian is the constant S_k
// (the columns of S for block k) at every x — this is what keeps the prior consistent
// with its linearisation point. Ceres asks for the Jacobian w.r.t. the ambient
// parameters and multiplies it by PlusJacobian(x_k); returning S_k·MinusJacobian(x_k)
// gives exactly S_k after that product, because Ceres requires
// MinusJacobian(x)·PlusJacobian(x) = I for every manifold.

#include <ceres/cost_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <vector>

namespace omnidso {

struct PriorBlock {
  int ambient_size = 0;
  const ceres::Manifold* manifold = nullptr;  // not owned; nullptr = Euclidean
  Eigen::VectorXd linearization_point;        // x̄, ambient coordinates

  int tangentSize() const { return manifold ? manifold->TangentSize() : ambient_size; }
};

class MarginalizationPrior : public ceres::CostFunction {
 public:
  // S: rows × Σ tangent sizes, s: rows. Blocks in the order of S's column groups.
  MarginalizationPrior(std::vector<PriorBlock> blocks, Eigen::MatrixXd sqrt_information,
                       Eigen::VectorXd residual_at_linearization);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const std::vector<PriorBlock>& blocks() const { return blocks_; }
  const Eigen::MatrixXd& sqrtInformation() const { return S_; }
  const Eigen::VectorXd& residualAtLinearization() const { return s_; }
  // H* = SᵀS in the blocks' tangent coordinates.
  Eigen::MatrixXd information() const { return S_.transpose() * S_; }

  // δ(x) for one block: x ⊟ x̄ in the block's tangent space.
  static Eigen::VectorXd tangentDelta(const PriorBlock& block, const double* x);

 private:
  std::vector<PriorBlock> blocks_;
  std::vector<int> tangent_offsets_;
  Eigen::MatrixXd S_;
  Eigen::VectorXd s_;
};

}  // namespace omnidso
