// The initialiser's native level solve (initializer_solver.hpp): the objective with the
// points' and the frame's parts of the normal equations, iteration 0, and the
// Schur-complement step for the Levenberg–Marquardt iterations of Ceres 2.1's
// TrustRegionMinimizer (backend/levenberg_marquardt_loop.hpp, shared with the tracker).
#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <omnidso/backend/levenberg_marquardt_loop.hpp>
#include <omnidso/backend/robust_correction.hpp>
#include <omnidso/core/se3.hpp>
#include <omnidso/frontend/initializer_solver.hpp>
#include <omnidso/residuals/se3_manifold.hpp>

namespace omnidso {
namespace {

constexpr int kFrameSize = 8;  // δ (6), a, b
using Matrix8 = Eigen::Matrix<double, kFrameSize, kFrameSize>;
using Vector8 = Eigen::Matrix<double, kFrameSize, 1>;
using Residuals = InitializerPatches::Residuals;
using FrameJacobian = InitializerPatches::FrameJacobian;

// x: the pose and the affine (9 ambient numbers), and the points' inverse distances.
struct State {
  std::array<double, 9> frame{};
  std::vector<double> d;
};

// The normal equations at a point (header): H_ff, g_f; per point h_p, g_p and w_p.
struct Equations {
  Matrix8 H = Matrix8::Zero();
  Vector8 g = Vector8::Zero();
  Eigen::VectorXd h, g_p;
  Eigen::Matrix<double, Eigen::Dynamic, kFrameSize, Eigen::RowMajor> W;

  void reset(int n) {
    H.setZero();
    g.setZero();
    h.setZero(n);
    g_p.setZero(n);
    W.setZero(n, kFrameSize);
  }
  void swap(Equations& other) {
    std::swap(H, other.H);
    std::swap(g, other.g);
    h.swap(other.h);
    g_p.swap(other.g_p);
    W.swap(other.W);
  }
};

// E at x and, when asked for, the normal equations there and every patch's raw energy.
// Summed in Ceres's program order for DENSE_SCHUR (its residual blocks grouped by point,
// each point's regulariser before its patch, then the translation term and the prior).
// False where a residual or Jacobian is not finite (Ceres's evaluation fails). Without the
// equations, E = +∞ as soon as the sum of its terms (each ≥ 0) exceeds `bound`.
bool evaluate(const InitializerLevelProblem& p, const State& x, Equations* eq, double* cost,
              std::vector<double>* energies,
              double bound = std::numeric_limits<double>::infinity()) {
  const int n = p.patches->size();
  p.patches->setPoint(x.frame.data(), x.frame.data() + 7);
  if (eq) eq->reset(n);
  if (energies) energies->assign(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  const Residuals penalty = Residuals::Constant(p.invalid_residual);
  const double invalid_cost = RobustCorrection(p.loss, penalty.squaredNorm()).cost();
  const double sqrt_lambda = p.regularizer_sqrt_weight;
  double sum = 0.0;
  Residuals r, J_d;
  FrameJacobian J_f;
  for (int i = 0; i < n; ++i) {
    const double d = x.d[static_cast<size_t>(i)];
    const double r_reg = sqrt_lambda * (d - p.regularizer_mean);  // r = √λ (d − d̄)
    if (!std::isfinite(r_reg)) return false;
    sum += 0.5 * r_reg * r_reg;
    if (eq) {
      eq->h[i] = sqrt_lambda * sqrt_lambda;
      eq->g_p[i] = sqrt_lambda * r_reg;
    }
    if (!p.patches->evaluate(i, d, &r, eq ? &J_f : nullptr, eq ? &J_d : nullptr)) {
      sum += invalid_cost;  // out_of_bounds_penalty.hpp: constant, zero Jacobian
      continue;
    }
    if (!r.allFinite() || (eq && !(J_f.allFinite() && J_d.allFinite()))) return false;
    const double energy = r.squaredNorm();
    if (energies) (*energies)[static_cast<size_t>(i)] = energy;
    const RobustCorrection correction(p.loss, energy);
    sum += correction.cost();
    if (!eq) {
      if (sum > bound) {  // the partial sums only grow: E > bound
        *cost = std::numeric_limits<double>::infinity();
        return true;
      }
      continue;
    }
    correction.correctJacobian(r, J_f);
    correction.correctJacobian(r, J_d);
    correction.correctResiduals(r);
    eq->H.noalias() += J_f.transpose() * J_f;
    eq->g.noalias() += J_f.transpose() * r;
    eq->h[i] += J_d.squaredNorm();
    eq->g_p[i] += J_d.dot(r);
    eq->W.row(i).noalias() = J_d.transpose() * J_f;
  }
  if (p.translation_sqrt_weight > 0) {
    // r_t = √(λN) t; tangent Jacobian √(λN) [R 0] (t of T exp(δ) moves with R ρ).
    const Eigen::Vector3d r_t = p.translation_sqrt_weight * Eigen::Vector3d(x.frame[4], x.frame[5], x.frame[6]);
    sum += 0.5 * r_t.squaredNorm();
    if (eq) {
      const Eigen::Matrix3d J_t =
          p.translation_sqrt_weight * SE3d::fromParameters(x.frame.data()).rotationMatrix();
      eq->H.topLeftCorner<3, 3>().noalias() += J_t.transpose() * J_t;
      eq->g.head<3>().noalias() += J_t.transpose() * r_t;
    }
  }
  if (p.affine_prior_weight_a > 0 || p.affine_prior_weight_b > 0) {
    // backend/affine_prior.hpp about [0, 0]: r = √w x, J = diag(√w), no loss.
    const double sqrt_wa = std::sqrt(p.affine_prior_weight_a);
    const double sqrt_wb = std::sqrt(p.affine_prior_weight_b);
    const double ra = sqrt_wa * x.frame[7], rb = sqrt_wb * x.frame[8];
    sum += 0.5 * (ra * ra + rb * rb);
    if (eq) {
      eq->H(6, 6) += sqrt_wa * sqrt_wa;
      eq->H(7, 7) += sqrt_wb * sqrt_wb;
      eq->g[6] += sqrt_wa * ra;
      eq->g[7] += sqrt_wb * rb;
    }
  }
  *cost = sum;
  return true;
}

// ‖r_p‖² of every patch at x, +∞ where invalid (the energies where evaluate() fails).
std::vector<double> rawEnergies(const InitializerLevelProblem& p, const State& x) {
  p.patches->setPoint(x.frame.data(), x.frame.data() + 7);
  std::vector<double> energies(x.d.size(), std::numeric_limits<double>::infinity());
  Residuals r;
  for (size_t i = 0; i < x.d.size(); ++i)
    if (p.patches->evaluate(static_cast<int>(i), x.d[i], &r, nullptr, nullptr))
      energies[i] = r.squaredNorm();
  return energies;
}

// x ⊞ δ: the pose by SE3Manifold, the affine and the inverse distances by addition.
void plus(const State& x, const Vector8& delta_f, const Eigen::VectorXd& delta_p, State* out) {
  SE3Manifold().Plus(x.frame.data(), delta_f.data(), out->frame.data());
  out->frame[7] = x.frame[7] + delta_f[6];
  out->frame[8] = x.frame[8] + delta_f[7];
  out->d.resize(x.d.size());
  for (size_t i = 0; i < x.d.size(); ++i) out->d[i] = x.d[i] + delta_p[static_cast<Eigen::Index>(i)];
}

double norm(const State& x) {
  double sum = 0.0;
  for (double v : x.frame) sum += v * v;
  for (double v : x.d) sum += v * v;
  return std::sqrt(sum);
}

double distance(const State& x, const State& y) {
  double sum = 0.0;
  for (size_t i = 0; i < x.frame.size(); ++i) sum += (x.frame[i] - y.frame[i]) * (x.frame[i] - y.frame[i]);
  for (size_t i = 0; i < x.d.size(); ++i) sum += (x.d[i] - y.d[i]) * (x.d[i] - y.d[i]);
  return std::sqrt(sum);
}

// ‖x − (x ⊞ −g)‖_∞ (Ceres's gradient_max_norm), the unscaled gradient.
double gradientMaxNorm(const State& x, const Equations& eq) {
  std::array<double, 7> moved;
  const Vector8 minus_g = -eq.g;
  SE3Manifold().Plus(x.frame.data(), minus_g.data(), moved.data());
  double max_norm = 0.0;
  for (int i = 0; i < 7; ++i) max_norm = std::max(max_norm, std::abs(x.frame[i] - moved[i]));
  max_norm = std::max({max_norm, std::abs(eq.g[6]), std::abs(eq.g[7])});
  return eq.g_p.size() ? std::max(max_norm, eq.g_p.cwiseAbs().maxCoeff()) : max_norm;
}

// The Jacobi-scaled, damped step with the points eliminated (header); false where the
// Cholesky factorisation fails or the step is not finite. δ is returned unscaled.
bool solveStep(const Equations& eq, const Vector8& s_f, const Eigen::VectorXd& s_p,
               const LevenbergMarquardtDamping& damping, Vector8* delta_f,
               Eigen::VectorXd* delta_p, Eigen::VectorXd* inverse_damped) {
  const int n = static_cast<int>(eq.h.size());
  const Matrix8 scaled_H = s_f.asDiagonal() * eq.H * s_f.asDiagonal();
  Matrix8 lhs = scaled_H;
  for (int j = 0; j < kFrameSize; ++j) lhs(j, j) += damping.squaredDiagonal(scaled_H(j, j));
  Vector8 rhs = s_f.cwiseProduct(eq.g);
  // Σ_p w̃_pᵀw̃_p / A_p = S_f (Σ_p c_p w_pᵀw_p) S_f with c_p = s_p² / A_p, likewise the rhs.
  Matrix8 eliminated = Matrix8::Zero();
  Vector8 eliminated_rhs = Vector8::Zero();
  inverse_damped->resize(n);
  for (int i = 0; i < n; ++i) {
    const double scaled_h = s_p[i] * s_p[i] * eq.h[i];
    const double inverse = 1.0 / (scaled_h + damping.squaredDiagonal(scaled_h));  // 1 / A_p
    (*inverse_damped)[i] = inverse;
    const double c = s_p[i] * s_p[i] * inverse;
    const auto w = eq.W.row(i);
    eliminated.noalias() += (c * w.transpose()) * w;
    eliminated_rhs.noalias() += (c * eq.g_p[i]) * w.transpose();
  }
  lhs.noalias() -= s_f.asDiagonal() * eliminated * s_f.asDiagonal();
  rhs -= s_f.cwiseProduct(eliminated_rhs);
  const Eigen::LLT<Matrix8> cholesky(lhs);
  if (cholesky.info() != Eigen::Success) return false;
  const Vector8 y_f = cholesky.solve(rhs);
  const Vector8 scaled_y_f = s_f.cwiseProduct(y_f);  // S_f y_f
  *delta_f = -scaled_y_f;
  delta_p->resize(n);
  for (int i = 0; i < n; ++i) {  // y_p = (g̃_p − w̃_p y_f) / A_p, δ_p = −s_p y_p
    const double y_p = s_p[i] * (eq.g_p[i] - eq.W.row(i).dot(scaled_y_f)) * (*inverse_damped)[i];
    (*delta_p)[i] = -s_p[i] * y_p;
  }
  return delta_f->allFinite() && delta_p->allFinite();
}

// L = −δᵀg − ½ δᵀHδ (Ceres: −(J̃δ)ᵀ(r̃ + J̃δ/2)).
double modelCostChange(const Equations& eq, const Vector8& delta_f, const Eigen::VectorXd& delta_p) {
  const Eigen::VectorXd coupled = eq.W * delta_f;
  double curvature = delta_f.dot(eq.H * delta_f);
  for (Eigen::Index i = 0; i < delta_p.size(); ++i)
    curvature += delta_p[i] * (2.0 * coupled[i] + eq.h[i] * delta_p[i]);
  return -(delta_f.dot(eq.g) + delta_p.dot(eq.g_p)) - 0.5 * curvature;
}

// One level's state for runLevenbergMarquardt (levenberg_marquardt_loop.hpp): x, its
// equations and energies, the step with the points eliminated, and the candidate.
struct LevelIterations {
  const InitializerLevelProblem& problem;
  const Vector8& s_f;
  const Eigen::VectorXd& s_p;
  std::vector<double>& energies;  // ‖r_p‖² at x
  State x, candidate;
  Equations equations, candidate_equations;
  std::vector<double> candidate_energies;
  Vector8 delta_f;
  Eigen::VectorXd delta_p, inverse_damped;

  bool step(const LevenbergMarquardtDamping& damping, double* model_cost_change) {
    if (!solveStep(equations, s_f, s_p, damping, &delta_f, &delta_p, &inverse_damped))
      return false;
    *model_cost_change = modelCostChange(equations, delta_f, delta_p);
    return true;
  }
  bool evaluateCandidate(bool linearize, double* cost) {
    plus(x, delta_f, delta_p, &candidate);
    return evaluate(problem, candidate, linearize ? &candidate_equations : nullptr, cost,
                    &candidate_energies);
  }
  double candidateDistance() const { return distance(candidate, x); }
  void accept(bool linearized) {
    std::swap(x, candidate);
    std::swap(energies, candidate_energies);
    if (linearized) equations.swap(candidate_equations);
  }
  double norm() const { return omnidso::norm(x); }
  double gradientMaxNorm() const { return omnidso::gradientMaxNorm(x, equations); }
};

InitializerTermination initializerTermination(LevenbergMarquardtTermination t) {
  switch (t) {
    case LevenbergMarquardtTermination::kConvergence: return InitializerTermination::kConvergence;
    case LevenbergMarquardtTermination::kNoConvergence:
      return InitializerTermination::kNoConvergence;
    case LevenbergMarquardtTermination::kFailure: break;
  }
  return InitializerTermination::kFailure;
}

}  // namespace

double initializerLevelCost(const InitializerLevelProblem& problem, const double* pose,
                            const double* affine, const std::vector<double>& inverse_distances,
                            double bound) {
  State x;
  std::copy_n(pose, 7, x.frame.begin());
  std::copy_n(affine, 2, x.frame.begin() + 7);
  x.d = inverse_distances;
  double cost = 0.0;
  return evaluate(problem, x, nullptr, &cost, nullptr, bound)
             ? cost
             : std::numeric_limits<double>::infinity();
}

InitializerSolverSummary solveInitializerLevel(const InitializerLevelProblem& problem,
                                               const InitializerSolverOptions& options,
                                               double* pose, double* affine,
                                               std::vector<double>* inverse_distances) {
  InitializerSolverSummary summary;
  Vector8 s_f = Vector8::Ones();
  Eigen::VectorXd s_p;
  LevelIterations it{problem, s_f, s_p, summary.energies, {}, {}, {}, {}, {}, {}, {}, {}};
  State& x = it.x;
  std::copy_n(pose, 7, x.frame.begin());
  std::copy_n(affine, 2, x.frame.begin() + 7);
  x.d = *inverse_distances;
  const int n = static_cast<int>(x.d.size());

  // Iteration 0.
  double x_cost = 0.0;
  if (!evaluate(problem, x, &it.equations, &x_cost, &summary.energies)) {
    summary.energies = rawEnergies(problem, x);
    return summary;  // kFailure, the start in place
  }
  const std::vector<double> start_energies = summary.energies;
  summary.initial_cost = x_cost;
  // Jacobi scaling from iteration 0's Jacobian: s_j = 1 / (1 + ‖J̃_j‖), ‖J̃_j‖² = H_jj.
  s_p = Eigen::VectorXd::Ones(n);
  if (options.jacobi_scaling) {
    for (int j = 0; j < kFrameSize; ++j) s_f[j] = 1.0 / (1.0 + std::sqrt(it.equations.H(j, j)));
    for (int i = 0; i < n; ++i) s_p[i] = 1.0 / (1.0 + std::sqrt(it.equations.h[i]));
  }
  const LevenbergMarquardtRun run = runLevenbergMarquardt(it, options, x_cost);
  summary.termination = initializerTermination(run.termination);
  recordRun(run, &summary);
  if (summary.termination == InitializerTermination::kFailure) {
    summary.energies = start_energies;
    return summary;
  }
  std::copy_n(x.frame.begin(), 7, pose);
  std::copy_n(x.frame.begin() + 7, 2, affine);
  *inverse_distances = x.d;
  return summary;
}

}  // namespace omnidso
