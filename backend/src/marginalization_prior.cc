#include <omnidso/backend/marginalization_prior.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {

MarginalizationPrior::MarginalizationPrior(std::vector<PriorBlock> blocks,
                                           Eigen::MatrixXd sqrt_information,
                                           Eigen::VectorXd residual_at_linearization)
    : blocks_(std::move(blocks)),
      S_(std::move(sqrt_information)),
      s_(std::move(residual_at_linearization)) {
  int offset = 0;
  for (const PriorBlock& b : blocks_) {
    if (b.linearization_point.size() != b.ambient_size)
      throw Error("MarginalizationPrior: linearisation point size differs from block size");
    tangent_offsets_.push_back(offset);
    offset += b.tangentSize();
    mutable_parameter_block_sizes()->push_back(b.ambient_size);
  }
  if (S_.cols() != offset || S_.rows() != s_.size())
    throw Error("MarginalizationPrior: square-root information has the wrong shape");
  set_num_residuals(static_cast<int>(S_.rows()));
}

Eigen::VectorXd MarginalizationPrior::tangentDelta(const PriorBlock& block, const double* x) {
  Eigen::VectorXd delta(block.tangentSize());
  if (block.manifold) {
    block.manifold->Minus(x, block.linearization_point.data(), delta.data());
  } else {
    delta = Eigen::Map<const Eigen::VectorXd>(x, block.ambient_size) - block.linearization_point;
  }
  return delta;
}

bool MarginalizationPrior::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  Eigen::Map<Eigen::VectorXd> r(residuals, num_residuals());
  r = s_;
  for (size_t k = 0; k < blocks_.size(); ++k) {
    const PriorBlock& b = blocks_[k];
    r.noalias() += S_.middleCols(tangent_offsets_[k], b.tangentSize()) *
                   tangentDelta(b, parameters[k]);
  }
  if (!jacobians) return true;
  for (size_t k = 0; k < blocks_.size(); ++k) {
    if (!jacobians[k]) continue;
    const PriorBlock& b = blocks_[k];
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
        jacobians[k], num_residuals(), b.ambient_size);
    const auto S_k = S_.middleCols(tangent_offsets_[k], b.tangentSize());
    if (b.manifold) {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> minus_jacobian(
          b.tangentSize(), b.ambient_size);
      if (!b.manifold->MinusJacobian(parameters[k], minus_jacobian.data())) return false;
      J.noalias() = S_k * minus_jacobian;
    } else {
      J = S_k;
    }
  }
  return true;
}

}  // namespace omnidso
