#pragma once
// Wraps a cost function so that, inside an iteration-limited solve, it avoids the evaluation
// Ceres makes after the last step and never uses (evaluation_reuse.hpp): it keeps the
// residuals of the last candidate point, and when Ceres then asks for residuals and
// Jacobian at that point it copies the residuals and returns zero Jacobians. Everything else
// goes to the wrapped cost function as asked. The wrapped cost function computes the same
// numbers at the same point whenever it is called, so the copy is bit for bit what a
// re-evaluation would give. (A Ceres residual block is evaluated by one thread at a time,
// so the kept values need no lock.)

#include <ceres/cost_function.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "omnidso/residuals/evaluation_reuse.hpp"
#include "omnidso/residuals/zero_jacobians.hpp"

namespace omnidso {

class ReusingCostFunction final : public ceres::CostFunction {
 public:
  // Takes ownership of `inner`; `reuse` must outlive the cost function.
  ReusingCostFunction(ceres::CostFunction* inner, const EvaluationReuse* reuse)
      : inner_(inner), reuse_(reuse), kept_residuals_(inner->num_residuals()) {
    set_num_residuals(inner_->num_residuals());
    *mutable_parameter_block_sizes() = inner_->parameter_block_sizes();
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (!jacobians && reuse_->keepResiduals()) {
      kept_ok_ = inner_->Evaluate(parameters, kept_residuals_.data(), nullptr);
      kept_point_ = reuse_->point();
      kept_valid_ = true;
      if (kept_ok_) std::copy(kept_residuals_.begin(), kept_residuals_.end(), residuals);
      return kept_ok_;
    }
    if (!jacobians || !reuse_->jacobiansUnused())
      return inner_->Evaluate(parameters, residuals, jacobians);
    // Residuals (kept ones where this is the kept point) and zero Jacobians.
    if (kept_valid_ && kept_point_ == reuse_->point()) {
      if (!kept_ok_) return false;  // as the evaluation it stands for
      std::copy(kept_residuals_.begin(), kept_residuals_.end(), residuals);
    } else if (!inner_->Evaluate(parameters, residuals, nullptr)) {
      return false;
    }
    zeroJacobians(*this, jacobians);
    return true;
  }

  const ceres::CostFunction& inner() const { return *inner_; }

 private:
  std::unique_ptr<ceres::CostFunction> inner_;
  const EvaluationReuse* reuse_;
  mutable std::vector<double> kept_residuals_;  // at the last candidate point
  mutable std::uint64_t kept_point_ = 0;
  mutable bool kept_valid_ = false;
  mutable bool kept_ok_ = false;
};

}  // namespace omnidso
