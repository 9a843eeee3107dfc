// The native tracker solver (tracker_solver.hpp): the objective and its 8×8 normal equations,
// iteration 0, and the Jacobi-scaled step for the Levenberg–Marquardt iterations of Ceres
// 2.1's TrustRegionMinimizer (backend/levenberg_marquardt_loop.hpp, which the initialiser's
// level solve runs too).
#include <ceres/loss_function.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <omnidso/backend/robust_correction.hpp>
#include <omnidso/backend/levenberg_marquardt_loop.hpp>
#include <omnidso/frontend/tracker_solver.hpp>
#include <omnidso/residuals/se3_manifold.hpp>
#include <vector>

namespace omnidso {
namespace {

constexpr int kTangentSize = 8;  // δ (6), a, b
constexpr int kAmbientSize = 9;  // [qx qy qz qw tx ty tz], a, b
using Matrix8 = Eigen::Matrix<double, kTangentSize, kTangentSize>;
using Vector8 = Eigen::Matrix<double, kTangentSize, 1>;
using Point = std::array<double, kAmbientSize>;  // x: the pose, then the affine

// E at a point and, when asked for, H = J̃ᵀJ̃ and g = J̃ᵀr̃ there.
struct NormalEquations {
  Matrix8 H = Matrix8::Zero();
  Vector8 g = Vector8::Zero();
};

class Objective {
 public:
  explicit Objective(const TrackerProblem& problem)
      : problem_(problem), loss_(problem.huber_threshold) {
    active_.reserve(static_cast<size_t>(problem.residuals->size()));
  }

  // Iteration 0: keeps the residuals valid at x — the rest are left out, as the Ceres path
  // leaves them out of its Problem — and evaluates E, H, g over them. False where the
  // evaluation fails; numActive() tells how many were kept.
  bool selectAndEvaluate(const Point& x, NormalEquations* equations, double* cost) {
    active_.clear();
    return evaluate(x, equations, cost, true);
  }
  int numActive() const { return static_cast<int>(active_.size()); }

  // E at x (Ceres's order: the residuals, then the prior) and, if `equations` is not null,
  // H and g. False where Ceres's evaluation fails (a residual or Jacobian not finite).
  bool evaluate(const Point& x, NormalEquations* equations, double* cost) {
    return evaluate(x, equations, cost, false);
  }

 private:
  bool evaluate(const Point& x, NormalEquations* equations, double* cost, bool select) {
    problem_.residuals->setPoint(x.data(), x.data() + 7);
    double sum = 0.0;
    if (equations) *equations = NormalEquations();
    Eigen::Matrix<double, 1, 1> r;
    Eigen::Matrix<double, 1, kTangentSize> J;
    const int n = select ? problem_.residuals->size() : numActive();
    for (int k = 0; k < n; ++k) {
      const int i = select ? k : active_[static_cast<size_t>(k)];
      if (!problem_.residuals->evaluate(i, r.data(), equations ? J.data() : nullptr)) {
        if (select) continue;               // invalid at the start: left out
        r[0] = problem_.invalid_residual;  // out_of_bounds_penalty.hpp
        J.setZero();
      }
      if (select) active_.push_back(i);
      if (!std::isfinite(r[0]) || (equations && !J.allFinite())) return false;
      const RobustCorrection correction(&loss_, r[0] * r[0]);
      sum += correction.cost();
      if (!equations) continue;
      correction.correctJacobian(r, J);
      correction.correctResiduals(r);
      equations->H.noalias() += J.transpose() * J;
      equations->g.noalias() += J.transpose() * r[0];
    }
    if (problem_.affine_prior_weight_a > 0 || problem_.affine_prior_weight_b > 0) {
      // backend/affine_prior.hpp: r = √w (x − x̄), J = diag(√w), no loss.
      const double sqrt_wa = std::sqrt(problem_.affine_prior_weight_a);
      const double sqrt_wb = std::sqrt(problem_.affine_prior_weight_b);
      const double ra = sqrt_wa * (x[7] - problem_.affine_prior_mean[0]);
      const double rb = sqrt_wb * (x[8] - problem_.affine_prior_mean[1]);
      sum += 0.5 * (ra * ra + rb * rb);
      if (equations) {
        equations->H(6, 6) += sqrt_wa * sqrt_wa;
        equations->H(7, 7) += sqrt_wb * sqrt_wb;
        equations->g[6] += sqrt_wa * ra;
        equations->g[7] += sqrt_wb * rb;
      }
    }
    *cost = sum;
    return true;
  }

  const TrackerProblem& problem_;
  ceres::HuberLoss loss_;
  std::vector<int> active_;
};

// x ⊞ δ: the pose by SE3Manifold, the affine by addition.
Point plus(const Point& x, const Vector8& delta) {
  Point out;
  SE3Manifold().Plus(x.data(), delta.data(), out.data());
  out[7] = x[7] + delta[6];
  out[8] = x[8] + delta[7];
  return out;
}

using AmbientVector = Eigen::Map<const Eigen::Matrix<double, kAmbientSize, 1>>;

double norm(const Point& x) { return AmbientVector(x.data()).norm(); }

double distance(const Point& x, const Point& y) {
  return (AmbientVector(x.data()) - AmbientVector(y.data())).norm();
}

// ‖x − (x ⊞ −g)‖_∞ (Ceres's gradient_max_norm).
double gradientMaxNorm(const Point& x, const Vector8& g) {
  const Point moved = plus(x, -g);
  double max_norm = 0.0;
  for (int i = 0; i < kAmbientSize; ++i) max_norm = std::max(max_norm, std::abs(x[i] - moved[i]));
  return max_norm;
}

// The tracker's state for runLevenbergMarquardt (levenberg_marquardt_loop.hpp): the Jacobi-
// scaled step on the 8×8 system, (SHS + D²) y = S g, δ = −S y, L = −δᵀg − ½ δᵀHδ.
struct TrackerIterations {
  Objective& objective;
  const Vector8& scaling;
  Point x;
  NormalEquations equations, candidate_equations;
  Point candidate;
  Vector8 delta;
  Eigen::LLT<Matrix8> cholesky;

  bool step(const LevenbergMarquardtDamping& damping, double* model_cost_change) {
    const Matrix8 scaled_H = scaling.asDiagonal() * equations.H * scaling.asDiagonal();
    Matrix8 lhs = scaled_H;
    for (int j = 0; j < kTangentSize; ++j) lhs(j, j) += damping.squaredDiagonal(scaled_H(j, j));
    cholesky.compute(lhs);
    const Vector8 scaled_gradient = scaling.cwiseProduct(equations.g);
    const Vector8 scaled_step = -cholesky.solve(scaled_gradient);
    if (!(cholesky.info() == Eigen::Success && scaled_step.allFinite())) return false;
    *model_cost_change =
        -scaled_step.dot(scaled_gradient) - 0.5 * scaled_step.dot(scaled_H * scaled_step);
    delta = scaling.cwiseProduct(scaled_step);
    return true;
  }
  bool evaluateCandidate(bool linearize, double* cost) {
    candidate = plus(x, delta);
    return objective.evaluate(candidate, linearize ? &candidate_equations : nullptr, cost);
  }
  double candidateDistance() const { return distance(candidate, x); }
  void accept(bool linearized) {
    x = candidate;
    if (linearized) std::swap(equations, candidate_equations);
  }
  double norm() const { return omnidso::norm(x); }
  double gradientMaxNorm() const { return omnidso::gradientMaxNorm(x, equations.g); }
};

TrackerTermination trackerTermination(LevenbergMarquardtTermination t) {
  switch (t) {
    case LevenbergMarquardtTermination::kConvergence: return TrackerTermination::kConvergence;
    case LevenbergMarquardtTermination::kNoConvergence: return TrackerTermination::kNoConvergence;
    case LevenbergMarquardtTermination::kFailure: break;
  }
  return TrackerTermination::kFailure;
}

}  // namespace

TrackerSolverSummary solveTracker(const TrackerProblem& problem,
                                  const TrackerSolverOptions& options, double* pose,
                                  double* affine) {
  TrackerSolverSummary summary;
  Objective objective(problem);
  Vector8 scaling = Vector8::Ones();
  TrackerIterations it{objective, scaling, {}, {}, {}, {}, {}, {}};
  std::copy_n(pose, 7, it.x.begin());
  std::copy_n(affine, 2, it.x.begin() + 7);

  // Iteration 0.
  double x_cost = 0.0;
  const bool evaluated = objective.selectAndEvaluate(it.x, &it.equations, &x_cost);
  summary.num_residuals = objective.numActive();
  if (evaluated && summary.num_residuals < problem.min_residuals) return summary;  // kNotSolved
  if (!evaluated) {
    summary.termination = TrackerTermination::kFailure;
    return summary;
  }
  summary.initial_cost = x_cost;
  // Jacobi scaling from iteration 0's Jacobian: s_j = 1 / (1 + ‖J̃_j‖), ‖J̃_j‖² = H_jj.
  if (options.jacobi_scaling)
    for (int j = 0; j < kTangentSize; ++j)
      scaling[j] = 1.0 / (1.0 + std::sqrt(it.equations.H(j, j)));

  const LevenbergMarquardtRun run = runLevenbergMarquardt(it, options, x_cost);
  summary.termination = trackerTermination(run.termination);
  recordRun(run, &summary);
  if (summary.termination != TrackerTermination::kFailure) {
    std::copy_n(it.x.begin(), 7, pose);
    std::copy_n(it.x.begin() + 7, 2, affine);
  }
  return summary;
}

}  // namespace omnidso
