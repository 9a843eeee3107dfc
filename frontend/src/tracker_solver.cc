// The native tracker solver (tracker_solver.hpp): the objective and its 8×8 normal equations,
// then the Levenberg–Marquardt loop in the order of Ceres 2.1's TrustRegionMinimizer (the
// same order as window_solver.cc's): iteration 0, then per iteration the step, its
// validity, the candidate, the tolerances, accept or reject and the trust-region update.
#include <ceres/loss_function.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <omnidso/backend/robust_correction.hpp>
#include <omnidso/backend/trust_region.hpp>
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

}  // namespace

TrackerSolverSummary solveTracker(const TrackerProblem& problem,
                                  const TrackerSolverOptions& options, double* pose,
                                  double* affine) {
  TrackerSolverSummary summary;
  Point x;
  std::copy_n(pose, 7, x.begin());
  std::copy_n(affine, 2, x.begin() + 7);
  Objective objective(problem);
  NormalEquations equations, candidate_equations;

  // Iteration 0.
  double x_cost = 0.0;
  const bool evaluated = objective.selectAndEvaluate(x, &equations, &x_cost);
  summary.num_residuals = objective.numActive();
  if (evaluated && summary.num_residuals < problem.min_residuals) return summary;  // kNotSolved
  if (!evaluated) {
    summary.termination = TrackerTermination::kFailure;
    return summary;
  }
  summary.initial_cost = x_cost;
  // Jacobi scaling from iteration 0's Jacobian: s_j = 1 / (1 + ‖J̃_j‖), ‖J̃_j‖² = H_jj.
  Vector8 scaling = Vector8::Ones();
  if (options.jacobi_scaling)
    for (int j = 0; j < kTangentSize; ++j) scaling[j] = 1.0 / (1.0 + std::sqrt(equations.H(j, j)));
  double gradient_max_norm = gradientMaxNorm(x, equations.g);
  double x_norm = -1.0;  // Ceres's ‖x‖ until a step is accepted
  TrustRegion region{options.initial_trust_region_radius};
  LevenbergMarquardtDamping damping{region.radius, options.min_lm_diagonal,
                                    options.max_lm_diagonal};
  double iteration_cost = x_cost, least_cost = x_cost;
  bool step_successful = true;
  int iteration = 0, consecutive_invalid_steps = 0;
  Eigen::LLT<Matrix8> cholesky;

  while (true) {
    // The end of an iteration: record it, then the termination tests in Ceres's order.
    (step_successful ? summary.successful_steps : summary.unsuccessful_steps) += 1;
    least_cost = std::min(least_cost, iteration_cost);
    if (iteration >= options.max_num_iterations) {
      summary.termination = TrackerTermination::kNoConvergence;
      break;
    }
    if (step_successful && gradient_max_norm <= options.gradient_tolerance) {
      summary.termination = TrackerTermination::kConvergence;
      break;
    }
    if (region.radius <= options.min_trust_region_radius) {
      summary.termination = TrackerTermination::kConvergence;
      break;
    }
    ++iteration;

    // The step on the scaled system: (SHS + D²) y = S g, δ = −S y; L = −δᵀg − ½ δᵀHδ.
    damping.radius = region.radius;
    const Matrix8 scaled_H = scaling.asDiagonal() * equations.H * scaling.asDiagonal();
    Matrix8 lhs = scaled_H;
    for (int j = 0; j < kTangentSize; ++j) lhs(j, j) += damping.squaredDiagonal(scaled_H(j, j));
    cholesky.compute(lhs);
    const Vector8 scaled_gradient = scaling.cwiseProduct(equations.g);
    const Vector8 scaled_step = -cholesky.solve(scaled_gradient);
    bool step_valid = cholesky.info() == Eigen::Success && scaled_step.allFinite();
    const double model_cost_change =
        step_valid
            ? -scaled_step.dot(scaled_gradient) - 0.5 * scaled_step.dot(scaled_H * scaled_step)
            : 0.0;
    step_valid = step_valid && model_cost_change > 0.0;
    if (!step_valid) {
      if (++consecutive_invalid_steps >= options.max_num_consecutive_invalid_steps) {
        summary.termination = TrackerTermination::kFailure;  // the start stays in place
        break;
      }
      region.stepRejected();
      step_successful = false;
      iteration_cost = x_cost;
      continue;
    }
    consecutive_invalid_steps = 0;

    // The candidate x ⊞ δ, with its normal equations unless this is the last iteration (an
    // accepted candidate is the next linearisation point; window_solver.hpp explains).
    const Vector8 delta = scaling.cwiseProduct(scaled_step);
    const Point candidate = plus(x, delta);
    const bool linearize_candidate = iteration < options.max_num_iterations;
    double candidate_cost = std::numeric_limits<double>::max();
    bool candidate_linearized = objective.evaluate(
        candidate, linearize_candidate ? &candidate_equations : nullptr, &candidate_cost);
    if (!candidate_linearized) candidate_cost = std::numeric_limits<double>::max();
    candidate_linearized = candidate_linearized && linearize_candidate;
    if (distance(candidate, x) <=
        options.parameter_tolerance * (x_norm + options.parameter_tolerance)) {
      summary.termination = TrackerTermination::kConvergence;
      break;
    }
    const double cost_change = x_cost - candidate_cost;
    if (std::abs(cost_change) <= options.function_tolerance * x_cost) {
      summary.termination = TrackerTermination::kConvergence;
      break;
    }

    // Accept or reject.
    const double step_quality = candidate_cost >= std::numeric_limits<double>::max()
                                    ? std::numeric_limits<double>::lowest()
                                    : cost_change / model_cost_change;
    if (step_quality > options.min_relative_decrease) {
      x = candidate;
      x_norm = norm(x);
      x_cost = candidate_cost;
      if (candidate_linearized) {
        std::swap(equations, candidate_equations);
        gradient_max_norm = gradientMaxNorm(x, equations.g);
      }  // else the last iteration: the Jacobian there would go unused
      step_successful = true;
      iteration_cost = x_cost;
      region.stepAccepted(step_quality, options.max_trust_region_radius);
    } else {
      step_successful = false;
      iteration_cost = candidate_cost;
      region.stepRejected();
    }
  }

  summary.iterations = summary.successful_steps + summary.unsuccessful_steps - 1;
  summary.final_cost = least_cost;
  if (summary.termination != TrackerTermination::kFailure) {
    std::copy_n(x.begin(), 7, pose);
    std::copy_n(x.begin() + 7, 2, affine);
  }
  return summary;
}

}  // namespace omnidso
