#pragma once
// The objective the native window solver minimises: Ceres's cost of the window's problem,
//   E = Σ_photometric ½ρ(‖r‖²) + Σ_priors ½ρ(‖r‖²),
// and its Gauss–Newton normal equations in tangent coordinates (window_normal_equations.hpp).
// The photometric part comes from the model's WindowPhotometricTerms; the priors (affine,
// intrinsics, marginalisation — few) are evaluated generically through their own
// ceres::CostFunction: ambient Jacobians times the block's PlusJacobian (the manifold's
// ∂(x ⊞ δ)/∂δ at δ = 0), then the loss's correction, as ceres::ResidualBlock::Evaluate does.
// A prior whose blocks are all constant is Ceres's fixed cost: counted apart, not in the
// cost the solver's tolerances see.

#include <omnidso/backend/window_problem.hpp>
#include <vector>

namespace omnidso {

class WindowNormalEquations;

struct WindowCost {
  double variable = 0.0;  // Ceres's cost: every residual block with a variable parameter block
  double fixed = 0.0;     // Ceres's fixed_cost
  double total() const { return variable + fixed; }
};

// The cost at the values in the problem's blocks; with `equations` (reset to the problem's
// sizes here) also the normal equations; with `energies` the photometric residuals' raw
// energies (WindowPhotometricTerms::evaluate). With `first_estimate` (the same problem, its
// frames' and intrinsics' blocks at their first estimates, its points those of `problem`)
// the photometric terms' Jacobians are taken there (WindowPhotometricTerms::evaluateAt); the
// cost and the priors stay at `problem`'s values. False when a prior's cost function fails,
// as a failed evaluation in Ceres.
bool evaluateWindow(const WindowProblem& problem, WindowNormalEquations* equations,
                    WindowCost* cost, std::vector<double>* energies = nullptr,
                    const WindowProblem* first_estimate = nullptr);

}  // namespace omnidso
