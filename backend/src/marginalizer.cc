#include <omnidso/backend/marginalization_prior.hpp>
#include <omnidso/backend/marginalizer.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>
#include <algorithm>
#include <unordered_set>

namespace omnidso {
namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// One residual block of R: its parameter blocks as indices into the ordered blocks [M | K]
// (-1 for constant ones, which get no Jacobian) and its residuals at the current estimate.
struct LinearizedBlock {
  ceres::ResidualBlockId id = nullptr;
  std::vector<int> block_index;
  int num_residuals = 0;
  int jacobian_cols = 0;             // Σ tangent sizes of its non-constant blocks
  std::vector<double> r;             // at the current estimate
  std::vector<double> jacobian;      // num_residuals × jacobian_cols, row-major
};

// J of one residual block at the problem's current parameter values (loss function and
// manifolds applied, as in a solve), its non-constant blocks side by side in their order.
bool evaluateJacobian(const ceres::Problem& problem, const std::vector<int>& tangent_sizes,
                      LinearizedBlock& block) {
  const int n = block.num_residuals;
  const size_t num_blocks = block.block_index.size();
  std::vector<RowMatrix> parts(num_blocks);
  std::vector<double*> pointers(num_blocks, nullptr);
  for (size_t i = 0; i < num_blocks; ++i) {
    if (block.block_index[i] < 0) continue;  // constant: Ceres refuses its Jacobian
    parts[i].resize(n, tangent_sizes[block.block_index[i]]);
    pointers[i] = parts[i].data();
  }
  std::vector<double> residuals(n);
  double cost = 0.0;
  if (!problem.EvaluateResidualBlock(block.id, true, &cost, residuals.data(), pointers.data()))
    return false;
  block.jacobian.resize(static_cast<size_t>(n) * block.jacobian_cols);
  Eigen::Map<RowMatrix> J(block.jacobian.data(), n, block.jacobian_cols);
  int col = 0;
  for (const RowMatrix& part : parts) {
    if (part.size() == 0) continue;  // a constant block
    J.middleCols(col, part.cols()) = part;
    col += static_cast<int>(part.cols());
  }
  return true;
}

// Normal equations of the linearised R in δ coordinates, split [M | K]: H_MM (sparse: for
// points block-diagonal), H_KM and H_KK dense (K is a few keyframes), g over [M | K]. Each
// residual block adds its own dense JᵀJ, so no global Jacobian is formed.
struct NormalEquations {
  NormalEquations(int m, int k) : m(m), H_km(Eigen::MatrixXd::Zero(k, m)),
                                  H_kk(Eigen::MatrixXd::Zero(k, k)),
                                  g(Eigen::VectorXd::Zero(m + k)) {}
  int m;
  std::vector<Eigen::Triplet<double>> H_mm_entries;  // summed on assembly
  Eigen::MatrixXd H_km, H_kk;
  Eigen::VectorXd g;

  // Adds JᵀJ and Jᵀr₀ of one block; `offsets` place each ordered block in [M | K].
  void add(const LinearizedBlock& block, const std::vector<int>& offsets,
           const std::vector<int>& tangent_sizes, const Eigen::VectorXd& delta_current) {
    const Eigen::Map<const RowMatrix> J(block.jacobian.data(), block.num_residuals,
                                        block.jacobian_cols);
    std::vector<int> global, local;  // per non-constant block: offset in [M | K], in J
    Eigen::VectorXd delta(block.jacobian_cols);
    int col = 0;
    for (int index : block.block_index) {
      if (index < 0) continue;
      global.push_back(offsets[index]);
      local.push_back(col);
      delta.segment(col, tangent_sizes[index]) =
          delta_current.segment(offsets[index], tangent_sizes[index]);
      col += tangent_sizes[index];
    }
    local.push_back(col);
    // r(δ) ≈ r₀ + J δ with r₀ = r(x) − J (x ⊟ x̄).
    const Eigen::VectorXd r0 =
        Eigen::Map<const Eigen::VectorXd>(block.r.data(), block.num_residuals) - J * delta;
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd Jtr = J.transpose() * r0;
    for (size_t a = 0; a < global.size(); ++a) {
      const int size_a = local[a + 1] - local[a];
      g.segment(global[a], size_a) += Jtr.segment(local[a], size_a);
      for (size_t b = 0; b < global.size(); ++b) {
        const int size_b = local[b + 1] - local[b];
        const auto part = JtJ.block(local[a], local[b], size_a, size_b);
        const bool a_in_m = global[a] < m, b_in_m = global[b] < m;
        if (a_in_m && b_in_m) {
          for (int i = 0; i < size_a; ++i)
            for (int j = 0; j < size_b; ++j)
              H_mm_entries.emplace_back(global[a] + i, global[b] + j, part(i, j));
        } else if (!a_in_m && b_in_m) {
          H_km.block(global[a] - m, global[b], size_a, size_b) += part;
        } else if (!a_in_m && !b_in_m) {
          H_kk.block(global[a] - m, global[b] - m, size_a, size_b) += part;
        }  // H_MK = H_KMᵀ: not needed
      }
    }
  }
};

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
    if (n == 1) {  // a point's inverse distance: pseudoInverse's result, without the solver
      const double h = H_mm.coeff(group[0], group[0]);
      if (h > 0.0 && h > relative_threshold * h)
        triplets.emplace_back(group[0], group[0], 1.0 / h);
      continue;
    }
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
  std::vector<int> offsets, tangent_sizes;
  std::unordered_map<const double*, int> index_of;
  std::vector<Eigen::VectorXd> current(ordered.size()), first_estimate(ordered.size());
  int dim = 0, dim_removed = 0;
  for (size_t i = 0; i < ordered.size(); ++i) {
    index_of.emplace(ordered[i], static_cast<int>(i));
    offsets.push_back(dim);
    tangent_sizes.push_back(problem.ParameterBlockTangentSize(ordered[i]));
    dim += tangent_sizes.back();
    if (static_cast<int>(i) < num_removed_blocks) dim_removed = dim;
    const int n = problem.ParameterBlockSize(ordered[i]);
    current[i] = Eigen::Map<const Eigen::VectorXd>(ordered[i], n);
    const Eigen::VectorXd* lin = linearizationPoint(ordered[i]);
    first_estimate[i] = lin ? *lin : current[i];
  }

  // The prior's blocks, and x ⊟ x̄ at the current estimate.
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

  // 2. Linearise, one residual block at a time: r at the current estimate, J at the
  // first-estimate point. A residual that cannot be evaluated at the current estimate (its
  // point projects out of the target) carries no information there: it is left out of the
  // prior (and removed below).
  std::vector<LinearizedBlock> linearized;
  for (ceres::ResidualBlockId id : residual_blocks) {
    LinearizedBlock block;
    block.id = id;
    block.num_residuals = problem.GetCostFunctionForResidualBlock(id)->num_residuals();
    block.r.resize(block.num_residuals);
    double cost = 0.0;
    if (!problem.EvaluateResidualBlock(id, true, &cost, block.r.data(), nullptr)) {
      ++local_stats.num_unevaluable_residual_blocks;
      continue;
    }
    std::vector<double*> params;
    problem.GetParameterBlocksForResidualBlock(id, &params);
    for (double* p : params) {
      const auto it = index_of.find(p);
      block.block_index.push_back(it == index_of.end() ? -1 : it->second);
      if (it != index_of.end()) block.jacobian_cols += tangent_sizes[it->second];
    }
    linearized.push_back(std::move(block));
  }
  // The Jacobians at the first-estimate point; where some residual cannot be evaluated
  // there, all at the current estimate (which evaluates: r did).
  auto evaluateJacobians = [&] {
    for (LinearizedBlock& block : linearized)
      if (!evaluateJacobian(problem, tangent_sizes, block)) return false;
    return true;
  };
  for (size_t i = 0; i < ordered.size(); ++i)
    Eigen::Map<Eigen::VectorXd>(ordered[i], current[i].size()) = first_estimate[i];
  const bool fej_ok = !linearized.empty() && evaluateJacobians();
  for (size_t i = 0; i < ordered.size(); ++i)
    Eigen::Map<Eigen::VectorXd>(ordered[i], current[i].size()) = current[i];
  const bool evaluated = !linearized.empty() && (fej_ok || evaluateJacobians());

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
  if (!evaluated) {  // nothing to linearise: the blocks leave without a prior
    removeFromProblem();
    if (stats) *stats = local_stats;
    return nullptr;
  }
  local_stats.used_first_estimate_jacobians = fej_ok;

  // 3. Schur complement onto K. M can be hundreds of points while K is a few keyframes: H_MM
  // stays sparse (pseudo-inverted per coupled group), the K×K and K×M parts are dense.
  const int m = dim_removed, k = dim - dim_removed;
  NormalEquations normal(m, k);
  for (const LinearizedBlock& block : linearized)
    normal.add(block, offsets, tangent_sizes, delta_current);
  Eigen::SparseMatrix<double> H_mm(m, m);
  H_mm.setFromTriplets(normal.H_mm_entries.begin(), normal.H_mm_entries.end());
  const Eigen::SparseMatrix<double> H_mm_inv =
      blockPseudoInverse(H_mm, options_.eigenvalue_threshold);
  const Eigen::MatrixXd H_km_Hmm_inv = normal.H_km * H_mm_inv;
  Eigen::MatrixXd H_star = normal.H_kk - H_km_Hmm_inv * normal.H_km.transpose();
  H_star = 0.5 * (H_star + H_star.transpose());
  const Eigen::VectorXd g_star = normal.g.tail(k) - H_km_Hmm_inv * normal.g.head(m);

  removeFromProblem();
  const ceres::ResidualBlockId prior_id = addPrior(problem, kept, H_star, g_star, &local_stats);
  if (stats) *stats = local_stats;
  return prior_id;
}

Eigen::VectorXd Marginalizer::firstEstimate(const ceres::Problem& problem,
                                            const double* block) const {
  const Eigen::VectorXd* lin = linearizationPoint(block);
  return lin ? *lin
             : Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
                   block, problem.ParameterBlockSize(block)));
}

ceres::ResidualBlockId Marginalizer::addPrior(ceres::Problem& problem,
                                              const std::vector<double*>& kept,
                                              const Eigen::MatrixXd& H_star,
                                              const Eigen::VectorXd& g_star,
                                              MarginalizationStats* stats) {
  const int k = static_cast<int>(H_star.rows());
  if (k == 0) return nullptr;
  // 4. Square-root information of H*.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H_star);
  const Eigen::VectorXd& lambda = eig.eigenvalues();
  const double cutoff = options_.eigenvalue_threshold * std::max(lambda.maxCoeff(), 0.0);
  std::vector<int> kept_directions;
  for (int i = 0; i < lambda.size(); ++i)
    if (lambda[i] > cutoff && lambda[i] > 0) kept_directions.push_back(i);
  const int rank = static_cast<int>(kept_directions.size());
  if (stats) stats->prior_rank = rank;
  if (rank == 0) return nullptr;
  Eigen::MatrixXd S(rank, k);
  Eigen::VectorXd s(rank);
  for (int row = 0; row < rank; ++row) {
    const int i = kept_directions[row];
    const Eigen::VectorXd v = eig.eigenvectors().col(i);
    S.row(row) = std::sqrt(lambda[i]) * v.transpose();
    s[row] = v.dot(g_star) / std::sqrt(lambda[i]);
  }
  std::vector<PriorBlock> prior_blocks(kept.size());
  for (size_t i = 0; i < kept.size(); ++i) {
    prior_blocks[i].ambient_size = problem.ParameterBlockSize(kept[i]);
    prior_blocks[i].manifold = problem.GetManifold(kept[i]);
    prior_blocks[i].linearization_point = firstEstimate(problem, kept[i]);
  }
  // 5 (second half). First-estimate points for the blocks the prior now touches.
  for (size_t i = 0; i < kept.size(); ++i)
    linearization_points_.emplace(kept[i], prior_blocks[i].linearization_point);
  auto* prior = new MarginalizationPrior(std::move(prior_blocks), std::move(S), std::move(s));
  const ceres::ResidualBlockId prior_id = problem.AddResidualBlock(prior, nullptr, kept);
  if (stats) stats->num_prior_blocks = static_cast<int>(kept.size());
  return prior_id;
}

}  // namespace omnidso
