// The native window solver's objective (window_objective.hpp): the photometric terms of the
// camera model, then every prior through its own ceres::CostFunction, in the problem's order.
#include <omnidso/backend/robust_correction.hpp>
#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_objective.hpp>
#include <omnidso/backend/window_photometric_terms.hpp>

namespace omnidso {
namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// One prior: its cost, and with `equations` its J̃ᵀJ̃ and J̃ᵀr̃ in frame space. The tangent
// Jacobian of a manifold block is the cost function's ambient Jacobian times the manifold's
// PlusJacobian, as Ceres forms it.
bool addPrior(const WindowPrior& prior, WindowNormalEquations* equations, WindowCost* cost) {
  const int m = prior.cost->num_residuals();
  const size_t num_blocks = prior.blocks.size();
  std::vector<const double*> parameters(num_blocks);
  for (size_t i = 0; i < num_blocks; ++i) parameters[i] = prior.blocks[i].values;
  Eigen::VectorXd r(m);
  if (prior.fixed()) {
    if (!prior.cost->Evaluate(parameters.data(), r.data(), nullptr)) return false;
    cost->fixed += RobustCorrection(prior.loss, r.squaredNorm()).cost();
    return true;
  }
  std::vector<RowMatrix> ambient(num_blocks);
  std::vector<double*> jacobians(num_blocks, nullptr);
  for (size_t i = 0; i < num_blocks; ++i) {
    if (prior.blocks[i].constant) continue;
    ambient[i].resize(m, prior.blocks[i].ambient_size);
    jacobians[i] = ambient[i].data();
  }
  if (!prior.cost->Evaluate(parameters.data(), r.data(), equations ? jacobians.data() : nullptr))
    return false;
  const RobustCorrection correction(prior.loss, r.squaredNorm());
  cost->variable += correction.cost();
  if (!equations) return true;

  std::vector<RowMatrix> tangent(num_blocks);
  for (size_t i = 0; i < num_blocks; ++i) {
    const WindowPriorBlock& block = prior.blocks[i];
    if (block.constant) continue;
    if (block.manifold) {
      RowMatrix plus_jacobian(block.ambient_size, block.tangent_size);
      if (!block.manifold->PlusJacobian(block.values, plus_jacobian.data())) return false;
      tangent[i] = ambient[i] * plus_jacobian;
    } else {
      tangent[i] = ambient[i];
    }
    correction.correctJacobian(r, tangent[i]);
  }
  correction.correctResiduals(r);
  Eigen::MatrixXd& H = equations->frameHessian();
  Eigen::VectorXd& g = equations->frameGradient();
  for (size_t i = 0; i < num_blocks; ++i) {
    const WindowPriorBlock& a = prior.blocks[i];
    if (a.constant) continue;
    g.segment(a.tangent_offset, a.tangent_size).noalias() += tangent[i].transpose() * r;
    for (size_t j = 0; j < num_blocks; ++j) {
      const WindowPriorBlock& b = prior.blocks[j];
      if (b.constant) continue;
      H.block(a.tangent_offset, b.tangent_offset, a.tangent_size, b.tangent_size).noalias() +=
          tangent[i].transpose() * tangent[j];
    }
  }
  return true;
}

}  // namespace

bool WindowPrior::fixed() const {
  for (const WindowPriorBlock& b : blocks)
    if (!b.constant) return false;
  return true;
}

bool evaluateWindow(const WindowProblem& problem, WindowNormalEquations* equations,
                    WindowCost* cost, std::vector<double>* energies,
                    const WindowProblem* first_estimate) {
  if (equations)
    equations->reset(problem.frameSpaceSize(), static_cast<int>(problem.points.size()));
  *cost = WindowCost{};
  cost->variable = first_estimate && equations
                       ? problem.photometric->evaluateAt(problem, *first_estimate, equations, energies)
                       : problem.photometric->evaluate(problem, equations, energies);
  for (const WindowPrior& prior : problem.priors)
    if (!addPrior(prior, equations, cost)) return false;
  return true;
}

}  // namespace omnidso
