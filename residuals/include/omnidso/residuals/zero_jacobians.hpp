#pragma once
// Fills every requested Jacobian block of `cost` with zeros (Ceres passes nullptr for the
// blocks it does not want, e.g. constant ones): the exact Jacobian of a constant residual,
// and what cost-function wrappers return where a Jacobian is known to go unused.

#include <ceres/cost_function.h>

#include <algorithm>
#include <vector>

namespace omnidso {

inline void zeroJacobians(const ceres::CostFunction& cost, double** jacobians) {
  if (!jacobians) return;
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  for (size_t i = 0; i < sizes.size(); ++i)
    if (jacobians[i]) std::fill_n(jacobians[i], cost.num_residuals() * sizes[i], 0.0);
}

}  // namespace omnidso
