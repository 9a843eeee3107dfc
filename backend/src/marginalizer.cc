#include <omnidso/backend/marginalization_prior.hpp>
#include <omnidso/backend/marginalizer.hpp>

#include <ceres/crs_matrix.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>
#include <algorithm>
#include <unordered_set>

namespace omnidso {
namespace {

using SparseRowMajor = Eigen::SparseMatrix<double, Eigen::RowMajor>;

SparseRowMajor toSparse(const ceres::CRSMatrix& crs) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(crs.values.size());
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k)
      triplets.emplace_back(row, crs.cols[k], crs.values[k]);
  SparseRowMajor J(crs.num_rows, crs.num_cols);
  J.setFromTriplets(triplets.begin(), triplets.end());
  return J;
}

// Pseudo-inverse of a symmetric positive semi-definite matrix.
Eigen::MatrixXd pseudoInverse(const Eigen::MatrixXd& A, double relative_threshold) {
  if (A.size() == 0) return A;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  const double cutoff = relative_threshold * std::max(lambda.maxCoeff(), 0.0);
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(lambda.size());
  for (int i = 0; i < lambda.size(); ++i)
    if (lambda[i] > cutoff && lambda[i] > 0) inv[i] = 1.0 / lambda[i];
  return eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
}

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// H_MM⁺ exploiting its block structure: marginalising many points at once gives a
// block-diagonal H_MM (points share no residual), so each coupled group of coordinates is
// pseudo-inverted on its own instead of one dense m×m matrix.
Eigen::SparseMatrix<double> blockPseudoInverse(const Eigen::SparseMatrix<double>& H_mm,
                                               double relative_threshold) {
  const int m = static_cast<int>(H_mm.rows());
  std::vector<int> parent(m);
  for (int i = 0; i < m; ++i) parent[i] = i;
  for (int col = 0; col < H_mm.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(H_mm, col); it; ++it)
      parent[findRoot(parent, static_cast<int>(it.row()))] = findRoot(parent, col);
  std::vector<std::vector<int>> groups(m);
  for (int i = 0; i < m; ++i) groups[findRoot(parent, i)].push_back(i);
  std::vector<Eigen::Triplet<double>> triplets;
  for (const std::vector<int>& group : groups) {
    if (group.empty()) continue;
    const int n = static_cast<int>(group.size());
    Eigen::MatrixXd block(n, n);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) block(a, b) = H_mm.coeff(group[a], group[b]);
    const Eigen::MatrixXd inv = pseudoInverse(block, relative_threshold);
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b)
        if (inv(a, b) != 0.0) triplets.emplace_back(group[a], group[b], inv(a, b));
  }
  Eigen::SparseMatrix<double> out(m, m);
  out.setFromTriplets(triplets.begin(), triplets.end());
  return out;
}

}  // namespace

const Eigen::VectorXd* Marginalizer::linearizationPoint(const double* block) const {
  const auto it = linearization_points_.find(block);
  return it == linearization_points_.end() ? nullptr : &it->second;
}

ceres::ResidualBlockId Marginalizer::marginalize(ceres::Problem& problem,
                                                 const std::vector<double*>& blocks,
                                                 MarginalizationStats* stats) {
  MarginalizationStats local_stats;
  // 1. Residual blocks connected to M, in the problem's order (a parameter block's own list
  // is a hash set of addresses, whose order would change the prior's last bits from run to
  // run), and the Markov blanket K.
  std::unordered_set<double*> removed(blocks.begin(), blocks.end());
  std::unordered_set<ceres::ResidualBlockId> connected;
  for (double* block : blocks) {
    std::vector<ceres::ResidualBlockId> ids;
    problem.GetResidualBlocksForParameterBlock(block, &ids);
    connected.insert(ids.begin(), ids.end());
  }
  std::vector<ceres::ResidualBlockId> residual_blocks;
  if (!connected.empty()) {
    std::vector<ceres::ResidualBlockId> all;
    problem.GetResidualBlocks(&all);
    for (ceres::ResidualBlockId id : all)
      if (connected.count(id)) residual_blocks.push_back(id);
  }
  std::vector<double*> kept;
  std::unordered_set<double*> seen_kept;
  for (ceres::ResidualBlockId id : residual_blocks) {
    std::vector<double*> params;
    problem.GetParameterBlocksForResidualBlock(id, &params);
    for (double* p : params) {
      if (removed.count(p) || problem.IsParameterBlockConstant(p)) continue;
      if (seen_kept.insert(p).second) kept.push_back(p);
    }
  }
  // Deterministic column order of K: the order in which blocks were met above.
  std::vector<double*> ordered;
  for (double* b : blocks)
    if (!problem.IsParameterBlockConstant(b)) ordered.push_back(b);
  const int num_removed_blocks = static_cast<int>(ordered.size());
  ordered.insert(ordered.end(), kept.begin(), kept.end());

  // Tangent layout and first-estimate points.
  std::vector<int> offsets;
  std::vector<Eigen::VectorXd> current(ordered.size()), first_estimate(ordered.size());
  int dim = 0, dim_removed = 0;
  for (size_t i = 0; i < ordered.size(); ++i) {
    offsets.push_back(dim);
    dim += problem.ParameterBlockTangentSize(ordered[i]);
    if (static_cast<int>(i) < num_removed_blocks) dim_removed = dim;
    const int n = problem.ParameterBlockSize(ordered[i]);
    current[i] = Eigen::Map<const Eigen::VectorXd>(ordered[i], n);
    const Eigen::VectorXd* lin = linearizationPoint(ordered[i]);
    first_estimate[i] = lin ? *lin : current[i];
  }

  // 2. Linearise: r at the current estimate, J at the first-estimate point. A residual that
  // cannot be evaluated at the current estimate (its point projects out of the target)
  // carries no information there: it is left out of the prior (and removed below).
  ceres::Problem::EvaluateOptions eval;
  eval.parameter_blocks = ordered;
  eval.residual_blocks = residual_blocks;
  std::vector<double> r_current;
  // (An empty residual list means "all residuals" to Problem::Evaluate: never pass one.)
  bool evaluated = !residual_blocks.empty() &&
                   problem.Evaluate(eval, nullptr, &r_current, nullptr, nullptr);
  if (!evaluated && !residual_blocks.empty()) {
    std::vector<ceres::ResidualBlockId> evaluable;
    for (ceres::ResidualBlockId id : residual_blocks) {
      double cost = 0.0;
      if (problem.EvaluateResidualBlock(id, true, &cost, nullptr, nullptr)) evaluable.push_back(id);
    }
    local_stats.num_unevaluable_residual_blocks =
        static_cast<int>(residual_blocks.size() - evaluable.size());
    eval.residual_blocks = evaluable;
    r_current.clear();
    evaluated = !evaluable.empty() &&
                problem.Evaluate(eval, nullptr, &r_current, nullptr, nullptr);
  }
  // 5 (first half, also when nothing could be linearised). The problem no longer holds R or M.
  auto removeFromProblem = [&] {
    for (ceres::ResidualBlockId id : residual_blocks) problem.RemoveResidualBlock(id);
    for (double* b : blocks) {
      problem.RemoveParameterBlock(b);
      linearization_points_.erase(b);
    }
    local_stats.num_residual_blocks = static_cast<int>(residual_blocks.size());
    local_stats.num_marginalized_blocks = static_cast<int>(blocks.size());
  };
  // The Jacobian at the first-estimate point; where some residual cannot be evaluated there,
  // the one at the current estimate (which evaluates: r did).
  ceres::CRSMatrix jacobian_crs;
  bool fej_ok = false;
  if (evaluated) {
    for (size_t i = 0; i < ordered.size(); ++i)
      Eigen::Map<Eigen::VectorXd>(ordered[i], current[i].size()) = first_estimate[i];
    fej_ok = problem.Evaluate(eval, nullptr, nullptr, nullptr, &jacobian_crs);
    for (size_t i = 0; i < ordered.size(); ++i)
      Eigen::Map<Eigen::VectorXd>(ordered[i], current[i].size()) = current[i];
    evaluated = fej_ok || problem.Evaluate(eval, nullptr, nullptr, nullptr, &jacobian_crs);
  }
  if (!evaluated) {  // nothing to linearise: the blocks leave without a prior
    removeFromProblem();
    if (stats) *stats = local_stats;
    return nullptr;
  }
  const SparseRowMajor J = toSparse(jacobian_crs);
  local_stats.used_first_estimate_jacobians = fej_ok;

  std::vector<PriorBlock> prior_blocks(ordered.size());
  Eigen::VectorXd delta_current(dim);
  for (size_t i = 0; i < ordered.size(); ++i) {
    PriorBlock& pb = prior_blocks[i];
    pb.ambient_size = static_cast<int>(current[i].size());
    pb.manifold = problem.GetManifold(ordered[i]);
    pb.linearization_point = first_estimate[i];
    delta_current.segment(offsets[i], pb.tangentSize()) =
        MarginalizationPrior::tangentDelta(pb, ordered[i]);
  }
  const Eigen::VectorXd r0 =
      Eigen::Map<const Eigen::VectorXd>(r_current.data(), r_current.size()) - J * delta_current;

  // 3. Schur complement onto K.
  // J is sparse (each residual touches few blocks); M can be hundreds of points while K
  // is a few keyframes, so only the K×K and K×M parts are made dense.
  const Eigen::SparseMatrix<double> H = Eigen::SparseMatrix<double>(J.transpose()) * J;
  const Eigen::VectorXd g = J.transpose() * r0;
  const int m = dim_removed, k = dim - dim_removed;
  const Eigen::SparseMatrix<double> H_mm_inv =
      blockPseudoInverse(H.topLeftCorner(m, m), options_.eigenvalue_threshold);
  const Eigen::MatrixXd H_km = Eigen::MatrixXd(H.bottomLeftCorner(k, m));
  const Eigen::MatrixXd H_km_Hmm_inv = H_km * H_mm_inv;
  Eigen::MatrixXd H_star =
      Eigen::MatrixXd(H.bottomRightCorner(k, k)) - H_km_Hmm_inv * H_km.transpose();
  H_star = 0.5 * (H_star + H_star.transpose());
  const Eigen::VectorXd g_star = g.tail(k) - H_km_Hmm_inv * g.head(m);

  removeFromProblem();
  ceres::ResidualBlockId prior_id = nullptr;
  if (k > 0) {
    // 4. Square-root information of H*.
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H_star);
    const Eigen::VectorXd& lambda = eig.eigenvalues();
    const double cutoff = options_.eigenvalue_threshold * std::max(lambda.maxCoeff(), 0.0);
    std::vector<int> kept_directions;
    for (int i = 0; i < lambda.size(); ++i)
      if (lambda[i] > cutoff && lambda[i] > 0) kept_directions.push_back(i);
    const int rank = static_cast<int>(kept_directions.size());
    local_stats.prior_rank = rank;
    if (rank > 0) {
      Eigen::MatrixXd S(rank, k);
      Eigen::VectorXd s(rank);
      for (int row = 0; row < rank; ++row) {
        const int i = kept_directions[row];
        const Eigen::VectorXd v = eig.eigenvectors().col(i);
        S.row(row) = std::sqrt(lambda[i]) * v.transpose();
        s[row] = v.dot(g_star) / std::sqrt(lambda[i]);
      }
      std::vector<PriorBlock> kept_prior_blocks(prior_blocks.begin() + num_removed_blocks,
                                                prior_blocks.end());
      auto* prior = new MarginalizationPrior(std::move(kept_prior_blocks), std::move(S),
                                             std::move(s));
      prior_id = problem.AddResidualBlock(prior, nullptr, kept);
      local_stats.num_prior_blocks = static_cast<int>(kept.size());
      // 5 (second half). First-estimate points for the blocks the prior now touches.
      for (size_t i = num_removed_blocks; i < ordered.size(); ++i)
        linearization_points_.emplace(ordered[i], first_estimate[i]);
    }
  }
  if (stats) *stats = local_stats;
  return prior_id;
}

}  // namespace omnidso
