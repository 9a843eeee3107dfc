#pragma once
// Levenberg–Marquardt's trust region as Ceres 2.1 runs it (levenberg_marquardt_strategy.cc,
// trust_region_minimizer.cc), shared by the native solvers (window_solver.hpp,
// frontend/tracker_solver.hpp), which reproduce ceres::Solve without its per-block plumbing:
//   the step solves (JᵀJ + D²) y = Jᵀr, step = −y, with D² = clamp(diag JᵀJ, 1e-6, 1e32) / Δ
//   (Ceres forms D = √(clamp / Δ) and its solvers add D·D, so the square root is kept);
//   a step with quality ρ = actual / predicted decrease > 1e-3 is accepted:
//     Δ ← min(Δ / max(1/3, 1 − (2ρ − 1)³), Δ_max), ν ← 2;
//   a rejected or invalid one shrinks the region: Δ ← Δ/ν, ν ← 2ν.
// Δ starts at 1e4 (Ceres's initial_trust_region_radius); μ = 1/Δ is Marquardt's damping.

#include <algorithm>
#include <cmath>

namespace omnidso {

// Δ and the factor ν by which the next rejection shrinks it.
struct TrustRegion {
  double radius;
  double decrease_factor = 2.0;

  void stepAccepted(double step_quality, double max_radius) {
    radius = std::min(max_radius,
                      radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * step_quality - 1.0, 3)));
    decrease_factor = 2.0;
  }
  void stepRejected() {
    radius /= decrease_factor;
    decrease_factor *= 2.0;
  }
};

// The options both native solvers share, with Ceres 2.1's names and defaults
// (Solver::Options); each solver's options add what only it has.
struct LevenbergMarquardtOptions {
  int max_num_iterations = 50;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  double initial_trust_region_radius = 1e4;
  double max_trust_region_radius = 1e16;
  double min_trust_region_radius = 1e-32;
  double min_relative_decrease = 1e-3;
  double min_lm_diagonal = 1e-6;
  double max_lm_diagonal = 1e32;
  int max_num_consecutive_invalid_steps = 5;
};

struct LevenbergMarquardtDamping {
  double radius = 1e4;         // Δ: Ceres's trust-region radius (μ = 1/Δ)
  double min_diagonal = 1e-6;  // Ceres's min_lm_diagonal
  double max_diagonal = 1e32;  // Ceres's max_lm_diagonal

  // D² of one coordinate whose diagonal of JᵀJ is `jtj_diagonal`.
  double squaredDiagonal(double jtj_diagonal) const {
    const double clamped = std::min(std::max(jtj_diagonal, min_diagonal), max_diagonal);
    const double d = std::sqrt(clamped / radius);
    return d * d;
  }
};

}  // namespace omnidso
