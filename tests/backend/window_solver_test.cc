// The native window solver (backend/window_solver.hpp) against Ceres on the same rendered
// windows: its normal equations and reduced camera system against Ceres's own Jacobian
// (ceres::Problem::Evaluate), its step against the damped normal equations, whole solves
// against ceres::Solve, the gauge, the out-of-bounds energy, and determinism.
#include <ceres/crs_matrix.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cmath>
#include <iostream>
#include <omnidso/backend/marginalization_prior.hpp>
#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_objective.hpp>
#include <omnidso/backend/window_state.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>

#include "window_test_scenes.hpp"

namespace omnidso {
namespace {

using test::expectSameStateBitForBit;
using test::perturbedWindow;
using test::WindowScene;
using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor>;

constexpr int kNumKeyframes = 5;

const Camera& testCamera() { return test::sweepCamera(); }

const WindowScene& testScene() { return test::sweepScene(kNumKeyframes); }

WindowOptions solverOptions(bool native, bool optimize_intrinsics, int max_iterations) {
  WindowOptions options;
  options.max_keyframes = kNumKeyframes;
  options.optimize_intrinsics = optimize_intrinsics;
  options.max_iterations = max_iterations;
  options.native_solver = native;
  // The oracle, ceres::Solve, linearises every residual at x; so does the native solver here
  // (first-estimate Jacobians: window_first_estimate_test.cc).
  options.first_estimate_jacobians = false;
  return options;
}

void moveNewestKeyframe(SlidingWindow& window) {
  WindowKeyframe& kf = window.mutableKeyframe(window.keyframeIds().back());
  test::moveInCamera(kf.T_world_cam(), Eigen::Vector3d(0.01, 0, 0), Eigen::Vector3d(0.5, 0, 0))
      .toParameters(kf.pose.data());
}

// The perturbed window of sliding_window_test.cc with every kind of prior: affine priors,
// the intrinsics prior (when the intrinsics are optimised) and a marginalisation prior
// (keyframe 1 marginalised, linearised at the perturbed state); the newest keyframe moved
// again. No solve has run, so the state does not depend on the solver.
std::unique_ptr<SlidingWindow> windowWithPriors(const WindowOptions& options) {
  auto window = perturbedWindow(testCamera(), testScene(), options, kNumKeyframes);
  window->removeOutliers();
  window->marginalizeKeyframe(1);
  EXPECT_TRUE(window->hasPrior());
  moveNewestKeyframe(*window);
  return window;
}

// Ceres's linearisation of the window at its current values, in the native solver's
// variables (WindowState): columns = variable points, then the variable frame-space
// coordinates in order. J̃ and r̃ are Ceres's (loss and manifolds applied).
struct CeresLinearization {
  SparseRows J;
  Eigen::VectorXd r;
  double cost = 0.0;
  int num_point_columns = 0;
};

CeresLinearization linearizeWithCeres(SlidingWindow& window, const WindowProblem& native,
                                      const WindowVariables& variables) {
  std::vector<double*> blocks;
  for (size_t p = 0; p < native.points.size(); ++p)
    if (variables.point_variable[p]) blocks.push_back(native.points[p].inverse_distance);
  CeresLinearization out;
  out.num_point_columns = static_cast<int>(blocks.size());
  for (const WindowFrame& f : native.frames) {
    if (!f.pose_constant) blocks.push_back(f.pose);
    if (!f.affine_constant) blocks.push_back(f.affine);
  }
  if (!native.intrinsics_constant) blocks.push_back(native.intrinsics);
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = blocks;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  EXPECT_TRUE(window.mutableProblem().Evaluate(evaluate, &out.cost, &residuals, nullptr, &crs));
  EXPECT_EQ(crs.num_cols, out.num_point_columns + static_cast<int>(variables.frame_columns.size()));
  std::vector<Eigen::Triplet<double>> entries;
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k)
      entries.emplace_back(row, crs.cols[k], crs.values[k]);
  out.J.resize(crs.num_rows, crs.num_cols);
  out.J.setFromTriplets(entries.begin(), entries.end());
  out.r = Eigen::Map<const Eigen::VectorXd>(residuals.data(), residuals.size());
  return out;
}

// D² of Ceres's Levenberg–Marquardt at radius Δ, per coordinate of H's diagonal.
Eigen::VectorXd squaredLmDiagonal(const Eigen::VectorXd& diagonal, double radius) {
  return (diagonal.cwiseMax(1e-6).cwiseMin(1e32) / radius).cwiseSqrt().cwiseAbs2();
}

// Entry-wise: |a − b| ≤ tolerance · bound (bound ≥ 0, sums of absolute values of the terms).
void expectNearBounded(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                       const Eigen::MatrixXd& bound, double tolerance, const char* what) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  double worst = 0.0;
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < a.cols(); ++j) {
      const double error = std::abs(a(i, j) - b(i, j));
      EXPECT_LE(error, tolerance * bound(i, j)) << what << " (" << i << ", " << j << "): " << a(i, j)
                                                << " vs " << b(i, j);
      if (bound(i, j) > 0) worst = std::max(worst, error / bound(i, j));
    }
  std::cout << what << ": largest error / bound " << worst << "\n";
}

Eigen::MatrixXd lowerTriangle(const Eigen::MatrixXd& m) {
  return m.triangularView<Eigen::Lower>();
}

// Tolerance of the comparisons with Ceres's linearisation, relative to the sum of the
// absolute values of the terms of each entry (|J|ᵀ|J| and the like): a sum of n products has
// a rounding error below n·ε of that, and the Jacobians themselves differ by a few ε
// (Ceres forms J·P⁺·P for the poses, the native solver J_ε·Ad). With ≈ 10⁴ rows per entry
// at most, n·ε ≈ 2·10⁻¹²; 10⁻⁹ leaves a margin of 500, and a wrong term (a sign, a
// missing factor, a column in the wrong block) is an error of order 1 on this scale.
constexpr double kLinearizationTolerance = 1e-9;

class WindowSolverEquations : public ::testing::TestWithParam<bool> {};

// The native normal equations — H_ff, g_f and per point h_p, g_p, w_p — and the reduced
// camera system at two trust-region radii equal those formed from Ceres's Jacobian of the
// same window: the same cost, the same tangent Jacobian, the same Schur complement.
TEST_P(WindowSolverEquations, EqualCeresNormalEquationsAndSchurComplement) {
  const bool optimize_intrinsics = GetParam();
  auto window = windowWithPriors(solverOptions(true, optimize_intrinsics, 2));
  const std::optional<WindowProblem> native = window->nativeProblem();
  ASSERT_TRUE(native.has_value());
  int marginalization_priors = 0;
  for (const WindowPrior& prior : native->priors)
    marginalization_priors += dynamic_cast<const MarginalizationPrior*>(prior.cost) != nullptr;
  EXPECT_GE(marginalization_priors, 1);
  EXPECT_EQ(native->intrinsics_constant, !optimize_intrinsics);
  EXPECT_GT(native->points.size(), 150u);
  std::cout << native->points.size() << " points, " << native->residuals.size() << " residuals, "
            << native->priors.size() << " priors\n";

  WindowNormalEquations equations;
  WindowCost cost;
  ASSERT_TRUE(evaluateWindow(*native, &equations, &cost));
  const WindowState state(*native);
  const WindowVariables& variables = state.variables();
  const CeresLinearization ceres = linearizeWithCeres(*window, *native, variables);
  EXPECT_NEAR(cost.total(), ceres.cost, 1e-12 * ceres.cost);

  const SparseRows abs_J = ceres.J.cwiseAbs();
  const Eigen::MatrixXd H = Eigen::MatrixXd(SparseRows(ceres.J.transpose() * ceres.J));
  const Eigen::MatrixXd H_bound = Eigen::MatrixXd(SparseRows(abs_J.transpose() * abs_J));
  const Eigen::VectorXd g = ceres.J.transpose() * ceres.r;
  const Eigen::VectorXd g_bound = abs_J.transpose() * ceres.r.cwiseAbs();
  const int np = ceres.num_point_columns, nf = static_cast<int>(variables.frame_columns.size());

  // Native quantities in the same columns.
  std::vector<int> points;
  for (int p = 0; p < static_cast<int>(native->points.size()); ++p)
    if (variables.point_variable[p]) points.push_back(p);
  ASSERT_EQ(static_cast<int>(points.size()), np);
  Eigen::MatrixXd H_ff(nf, nf), W(np, nf);
  Eigen::VectorXd g_f(nf), h_p(np), g_p(np);
  for (int i = 0; i < nf; ++i) {
    g_f[i] = equations.frameGradient()[variables.frame_columns[i]];
    for (int j = 0; j < nf; ++j)
      H_ff(i, j) = equations.frameHessian()(variables.frame_columns[i], variables.frame_columns[j]);
    for (int k = 0; k < np; ++k) W(k, i) = equations.pointCoupling()(points[k], variables.frame_columns[i]);
  }
  for (int k = 0; k < np; ++k) {
    h_p[k] = equations.pointHessian()[points[k]];
    g_p[k] = equations.pointGradient()[points[k]];
  }
  // H_pp is diagonal (each residual sees one point).
  Eigen::MatrixXd H_pp_off_diagonal = H.topLeftCorner(np, np);
  H_pp_off_diagonal.diagonal().setZero();
  EXPECT_EQ(H_pp_off_diagonal.cwiseAbs().maxCoeff(), 0.0);
  expectNearBounded(H_ff, H.bottomRightCorner(nf, nf), H_bound.bottomRightCorner(nf, nf),
                    kLinearizationTolerance, "H_ff");
  expectNearBounded(W, H.bottomLeftCorner(nf, np).transpose(),
                    H_bound.bottomLeftCorner(nf, np).transpose(), kLinearizationTolerance, "W");
  expectNearBounded(h_p, H.topLeftCorner(np, np).diagonal(),
                    H_bound.topLeftCorner(np, np).diagonal(), kLinearizationTolerance, "h_p");
  expectNearBounded(g_f, g.tail(nf), g_bound.tail(nf), kLinearizationTolerance, "g_f");
  expectNearBounded(g_p, g.head(np), g_bound.head(np), kLinearizationTolerance, "g_p");

  // The reduced camera system S = H_ff + D_f² − H_fp (H_pp + D_p²)⁻¹ H_pf and its right-hand
  // side, from Ceres's H; the bound adds the absolute values of the Schur terms.
  for (const double radius : {1e4, 1e-1}) {
    SCOPED_TRACE("trust-region radius " + std::to_string(radius));
    const Eigen::VectorXd D2 = squaredLmDiagonal(H.diagonal(), radius);
    const Eigen::VectorXd inverse = (H.diagonal().head(np) + D2.head(np)).cwiseInverse();
    const Eigen::MatrixXd H_fp = H.bottomLeftCorner(nf, np), B_fp = H_bound.bottomLeftCorner(nf, np);
    Eigen::MatrixXd S = H.bottomRightCorner(nf, nf) - H_fp * inverse.asDiagonal() * H_fp.transpose();
    S.diagonal() += D2.tail(nf);
    const Eigen::VectorXd rhs = g.tail(nf) - H_fp * inverse.asDiagonal() * g.head(np);
    Eigen::MatrixXd S_bound = H_bound.bottomRightCorner(nf, nf) + B_fp * inverse.asDiagonal() * B_fp.transpose();
    S_bound.diagonal() += D2.tail(nf);
    const Eigen::VectorXd rhs_bound = g_bound.tail(nf) + B_fp * inverse.asDiagonal() * g_bound.head(np);

    Eigen::MatrixXd native_S;
    Eigen::VectorXd native_rhs;
    equations.reducedCameraSystem(variables, {radius, 1e-6, 1e32}, &native_S, &native_rhs);
    expectNearBounded(lowerTriangle(native_S), lowerTriangle(S), lowerTriangle(S_bound),
                      kLinearizationTolerance, "S");
    expectNearBounded(native_rhs, rhs, rhs_bound, kLinearizationTolerance, "S rhs");
  }
}

INSTANTIATE_TEST_SUITE_P(Intrinsics, WindowSolverEquations, ::testing::Values(true, false),
                         [](const auto& info) { return info.param ? "Optimised" : "Constant"; });

// The native step δ solves Ceres's damped normal equations (JᵀJ + D²)(−δ) = Jᵀr, JᵀJ from
// Ceres's own Jacobian, to the accuracy of a backward-stable solve, and its model cost
// change equals Ceres's −(Jδ)ᵀ(r + Jδ/2) computed from that Jacobian.
TEST(WindowSolverStep, SolvesTheDampedNormalEquationsOfCeresJacobian) {
  auto window = windowWithPriors(solverOptions(true, true, 2));
  const std::optional<WindowProblem> native = window->nativeProblem();
  ASSERT_TRUE(native.has_value());
  WindowNormalEquations equations;
  WindowCost cost;
  ASSERT_TRUE(evaluateWindow(*native, &equations, &cost));
  const WindowState state(*native);
  const WindowVariables& variables = state.variables();
  const CeresLinearization ceres = linearizeWithCeres(*window, *native, variables);
  const Eigen::MatrixXd H = Eigen::MatrixXd(SparseRows(ceres.J.transpose() * ceres.J));
  const Eigen::VectorXd g = ceres.J.transpose() * ceres.r;
  const int np = ceres.num_point_columns;

  for (const double radius : {1e4, 1e-1}) {
    SCOPED_TRACE("trust-region radius " + std::to_string(radius));
    Eigen::VectorXd frame_step, point_step;
    ASSERT_TRUE(equations.solveStep(variables, {radius, 1e-6, 1e32}, &frame_step, &point_step));
    Eigen::VectorXd step(H.cols());
    for (int k = 0, p = 0; p < static_cast<int>(native->points.size()); ++p)
      if (variables.point_variable[p]) step[k++] = point_step[p];
      else EXPECT_EQ(point_step[p], 0.0);  // the scale anchor does not move
    for (size_t i = 0; i < variables.frame_columns.size(); ++i)
      step[np + i] = frame_step[variables.frame_columns[i]];
    Eigen::MatrixXd damped = H;
    damped.diagonal() += squaredLmDiagonal(H.diagonal(), radius);
    // A backward-stable solve leaves ‖A x − b‖ ≲ c·n·ε·‖A‖‖x‖ (n ≈ 250 unknowns here); 1e-10
    // is a margin of ≈ 10³ over that, while a wrong step misses by order 1.
    const double residual = (damped * (-step) - g).norm();
    EXPECT_LE(residual, 1e-10 * (damped.norm() * step.norm() + g.norm()));
    const Eigen::VectorXd J_step = ceres.J * step;
    const double model_change = -J_step.dot(ceres.r + 0.5 * J_step);
    EXPECT_GT(model_change, 0.0);
    EXPECT_NEAR(equations.modelCostChange(frame_step, point_step), model_change,
                1e-9 * model_change);
  }
}

// swap() hands the solver's x and candidate equations to each other: afterwards each
// object solves for the other's step, bit for bit — also when one of them has never been
// solved (its Cholesky workspace never computed: std::swap read that uninitialised status,
// which UBSan reported in `make test-asan-ci`).
TEST(WindowSolverStep, SwappedEquationsSolveEachOthersStep) {
  auto window = windowWithPriors(solverOptions(true, true, 2));
  const std::optional<WindowProblem> native = window->nativeProblem();
  ASSERT_TRUE(native.has_value());
  const WindowState state(*native);
  WindowNormalEquations solved, fresh;
  WindowCost cost;
  ASSERT_TRUE(evaluateWindow(*native, &solved, &cost));
  const LevenbergMarquardtDamping damping{1e4, 1e-6, 1e32};
  Eigen::VectorXd frame_step, point_step;
  ASSERT_TRUE(solved.solveStep(state.variables(), damping, &frame_step, &point_step));
  const int frame_space = solved.frameSpaceSize(), points = solved.numPoints();
  ASSERT_GT(frame_space, 0);
  ASSERT_GT(points, 0);

  solved.swap(fresh);
  EXPECT_EQ(solved.frameSpaceSize(), 0);
  EXPECT_EQ(solved.numPoints(), 0);
  ASSERT_EQ(fresh.frameSpaceSize(), frame_space);
  ASSERT_EQ(fresh.numPoints(), points);
  Eigen::VectorXd frame_again, point_again;
  ASSERT_TRUE(fresh.solveStep(state.variables(), damping, &frame_again, &point_again));
  EXPECT_EQ(frame_again, frame_step);
  EXPECT_EQ(point_again, point_step);
}

// The largest differences between two windows' states: pose translation [m] and rotation
// [rad], affine, relative inverse distance, intrinsics.
struct StateDifference {
  double translation = 0, rotation = 0, affine = 0, inverse_distance = 0, intrinsics = 0;
};

StateDifference difference(const SlidingWindow& a, const SlidingWindow& b) {
  StateDifference d;
  EXPECT_EQ(a.keyframeIds(), b.keyframeIds());
  for (int id : a.keyframeIds()) {
    const SE3d Ta = a.keyframe(id).T_world_cam(), Tb = b.keyframe(id).T_world_cam();
    d.translation = std::max(d.translation, (Ta.translation() - Tb.translation()).norm());
    d.rotation = std::max(d.rotation, so3Log(Ta.rotation().conjugate() * Tb.rotation()).norm());
    for (int i = 0; i < 2; ++i)
      d.affine = std::max(d.affine, std::abs(a.keyframe(id).affine[i] - b.keyframe(id).affine[i]));
  }
  EXPECT_EQ(a.numPoints(), b.numPoints());
  for (const auto& [id, point] : a.points()) {
    const double other = b.points().at(id)->inverse_distance;
    d.inverse_distance = std::max(d.inverse_distance,
                                  std::abs(point->inverse_distance - other) / std::abs(other));
  }
  d.intrinsics = (a.intrinsics() - b.intrinsics()).cwiseAbs().maxCoeff();
  std::cout << "largest differences: translation " << d.translation << " m, rotation "
            << d.rotation << " rad, affine " << d.affine << ", inverse distance (relative) "
            << d.inverse_distance << ", intrinsics " << d.intrinsics << "\n";
  return d;
}

// Two solves from the same state differ by rounding only, amplified by the conditioning of
// the damped normal equations; measured ≈ 1e-13..1e-11 (m, rad, relative). The bounds are
// 10⁻⁸ — three orders above that, and far below what a different step, an accept/reject
// decision taken otherwise or a different trust-region radius would give (≥ 10⁻⁶ here, the
// size of the last steps).
// The initial costs: equal to rounding (1e-12) from the same state; after an earlier solve
// the states differ by that solve's rounding (≈ 1e-13 relative), which the marginalisation
// prior's large curvature turns into ≈ 1e-12 of the cost: 1e-9 there.
void expectSameSolution(const SlidingWindow& native, const SlidingWindow& ceres,
                        const WindowSolveSummary& native_summary,
                        const WindowSolveSummary& ceres_summary, double initial_cost_tolerance) {
  EXPECT_EQ(native_summary.linear_solver, "NATIVE_DENSE_SCHUR");
  EXPECT_EQ(native_summary.iterations, ceres_summary.iterations);
  EXPECT_EQ(native_summary.successful_iterations, ceres_summary.successful_iterations);
  EXPECT_EQ(native_summary.usable, ceres_summary.usable);
  EXPECT_EQ(native_summary.message, ceres_summary.message);
  EXPECT_EQ(native_summary.num_residuals, ceres_summary.num_residuals);
  EXPECT_NEAR(native_summary.initial_cost, ceres_summary.initial_cost,
              initial_cost_tolerance * ceres_summary.initial_cost);
  EXPECT_NEAR(native_summary.final_cost, ceres_summary.final_cost, 1e-6 * ceres_summary.final_cost);
  const StateDifference d = difference(native, ceres);
  EXPECT_LT(d.translation, 1e-8);
  EXPECT_LT(d.rotation, 1e-8);
  EXPECT_LT(d.affine, 1e-8);
  EXPECT_LT(d.inverse_distance, 1e-8);
  EXPECT_LT(d.intrinsics, 1e-8);  // pixels (fx … cy) and ξ
}

class WindowSolverAgainstCeres : public ::testing::TestWithParam<bool> {};

// The same window solved by ceres::Solve and by the native solver — 5 iterations, with the
// priors — then outliers removed, keyframe 2 marginalised (its points natively in the one,
// through the ceres::Problem in the other, at the native solver's result), the newest keyframe
// moved and both solved again: the same iterations, accepted steps, termination, costs and
// parameters.
TEST_P(WindowSolverAgainstCeres, ReachesTheSameSolution) {
  const bool optimize_intrinsics = GetParam();
  auto native = windowWithPriors(solverOptions(true, optimize_intrinsics, 5));
  auto ceres = windowWithPriors(solverOptions(false, optimize_intrinsics, 5));
  expectSameStateBitForBit(*native, *ceres);
  {
    SCOPED_TRACE("first solve");
    const WindowSolveSummary n = native->optimize(), c = ceres->optimize();
    EXPECT_EQ(c.linear_solver, "DENSE_SCHUR");
    EXPECT_LT(c.final_cost, c.initial_cost);
    // The priors of keyframe 1 come from the two marginalisation paths (the native one of
    // window_point_marginalization.hpp, Ceres's), equal to rounding: 1e-9 as below.
    expectSameSolution(*native, *ceres, n, c, 1e-9);
  }
  EXPECT_EQ(native->removeOutliers(), ceres->removeOutliers());
  native->marginalizeKeyframe(2);
  ceres->marginalizeKeyframe(2);
  moveNewestKeyframe(*native);
  moveNewestKeyframe(*ceres);
  {
    SCOPED_TRACE("after marginalisation");
    const WindowSolveSummary n = native->optimize(), c = ceres->optimize();
    expectSameSolution(*native, *ceres, n, c, 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Intrinsics, WindowSolverAgainstCeres, ::testing::Values(true, false),
                         [](const auto& info) { return info.param ? "Optimised" : "Constant"; });

// The gauge (sliding_window.hpp): the first keyframe's pose and affine block and the scale
// anchor's inverse distance come out of a native solve bit for bit unchanged (and the
// intrinsics when they are not optimised), while everything else moves.
TEST(WindowSolverGauge, ConstantBlocksStayBitIdentical) {
  auto window = perturbedWindow(testCamera(), testScene(), solverOptions(true, false, 3),
                                kNumKeyframes);
  std::map<int, std::array<double, 7>> poses;
  for (int id : window->keyframeIds()) poses[id] = window->keyframe(id).pose;
  const std::array<double, 2> first_affine = window->keyframe(0).affine;
  const Eigen::VectorXd intrinsics = window->intrinsics();
  std::map<int, double> before;
  for (const auto& [id, point] : window->points()) before[id] = point->inverse_distance;
  const WindowSolveSummary summary = window->optimize();
  ASSERT_EQ(summary.linear_solver, "NATIVE_DENSE_SCHUR");
  ASSERT_GE(summary.successful_iterations, 2);
  EXPECT_EQ(window->keyframe(0).pose, poses.at(0));
  EXPECT_EQ(window->keyframe(0).affine, first_affine);
  EXPECT_EQ(window->intrinsics(), intrinsics);
  const int anchor = window->scaleAnchorPointId();
  ASSERT_GE(anchor, 0);
  EXPECT_EQ(window->points().at(anchor)->inverse_distance, before.at(anchor));
  int unchanged = 0;
  for (const auto& [id, point] : window->points()) unchanged += point->inverse_distance == before.at(id);
  EXPECT_EQ(unchanged, 1);  // the anchor, and only the anchor
  for (int id : window->keyframeIds()) {
    if (id == 0) continue;
    EXPECT_NE(window->keyframe(id).pose, poses.at(id)) << "keyframe " << id;
  }
}

// OutOfBoundsPenalty's semantics: a residual that cannot be evaluated costs the outlier
// energy ½ρ(E), E = 12² · 8, under the block's Huber loss, with a zero Jacobian. A point
// given a negative inverse distance invalidates all its residuals: the native cost changes
// by exactly that against Ceres's costs of the same residual blocks before, and the point
// has no curvature, gradient or coupling; a keyframe turned by 60° sends many residuals
// out of the image, and the native cost still equals Ceres's.
TEST(WindowSolverOutOfBounds, InvalidResidualsCostTheOutlierEnergy) {
  const WindowOptions options = solverOptions(true, true, 2);
  auto window = perturbedWindow(testCamera(), testScene(), options, kNumKeyframes);
  std::optional<WindowProblem> native = window->nativeProblem();
  ASSERT_TRUE(native.has_value());
  WindowCost before;
  ASSERT_TRUE(evaluateWindow(*native, nullptr, &before));

  int index = 0;  // the first point with at least three residuals
  while (native->points[index].num_residuals < 3) ++index;
  const int id = std::next(window->points().begin(), index)->first;
  const WindowPoint& point = *window->points().at(id);
  double valid_costs = 0.0;
  ceres::Problem& problem = window->mutableProblem();  // every residual block in it
  for (const auto& [target, block] : point.residuals) {
    double c = 0.0;  // Ceres's cost of the block, loss applied
    ASSERT_TRUE(problem.EvaluateResidualBlock(block, true, &c, nullptr, nullptr));
    valid_costs += c;
  }
  const double delta = options.huber_threshold * std::sqrt(8.0);
  const double energy = options.outlier_energy_per_pixel * 8;
  ASSERT_GT(energy, delta * delta);  // Huber's linear part: ρ = 2δ√E − δ²
  const double outlier_cost = 0.5 * (2.0 * delta * std::sqrt(energy) - delta * delta);

  window->mutablePoint(id).inverse_distance = -1.0;
  WindowNormalEquations equations;
  WindowCost after;
  ASSERT_TRUE(evaluateWindow(*native, &equations, &after));
  const double expected =
      before.total() - valid_costs + static_cast<double>(point.residuals.size()) * outlier_cost;
  EXPECT_NEAR(after.total(), expected, 1e-12 * expected);
  EXPECT_EQ(equations.pointHessian()[index], 0.0);
  EXPECT_EQ(equations.pointGradient()[index], 0.0);
  EXPECT_EQ(equations.pointCoupling().row(index).cwiseAbs().maxCoeff(), 0.0);

  WindowKeyframe& newest = window->mutableKeyframe(kNumKeyframes - 1);
  test::moveInCamera(newest.T_world_cam(), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 60, 0))
      .toParameters(newest.pose.data());
  int invalid = 0;
  for (const auto& [pid, p] : window->points())
    for (const auto& [target, block] : p->residuals)
      invalid += std::isinf(rawEnergy(problem, block));
  EXPECT_GT(invalid, 20);
  ASSERT_TRUE(evaluateWindow(*native, nullptr, &after));
  double ceres_cost = 0.0;
  ASSERT_TRUE(problem.Evaluate({}, &ceres_cost, nullptr, nullptr, nullptr));
  EXPECT_NEAR(after.total(), ceres_cost, 1e-12 * ceres_cost);
}

// Two windows built from the same data, with unrelated allocations in between (another heap
// layout), come out of native solves — a solve, marginalisation, another solve — bit for bit
// equal: everything is summed in point-id and keyframe order.
// A native solve, marginalisation, another solve, on the window with priors; the window and
// the two solves' final costs. `pool`: the solver's compute threads (null: none).
std::tuple<std::unique_ptr<SlidingWindow>, double, double> solveMarginalizeSolve(TaskPool* pool) {
  auto window = windowWithPriors(solverOptions(true, true, 3));
  window->setTaskPool(pool);
  const WindowSolveSummary first = window->optimize();
  window->removeOutliers();
  window->marginalizeKeyframe(2);
  moveNewestKeyframe(*window);
  const WindowSolveSummary second = window->optimize();
  EXPECT_EQ(second.linear_solver, "NATIVE_DENSE_SCHUR");
  EXPECT_GT(first.iterations, 0);
  return std::make_tuple(std::move(window), first.final_cost, second.final_cost);
}

TEST(WindowSolverDeterminism, SolvesBitForBitIndependentlyOfTheHeapLayout) {
  const auto [a, a_first, a_second] = solveMarginalizeSolve(nullptr);
  std::vector<std::unique_ptr<double[]>> clutter;
  for (int i = 0; i < 1000; ++i) clutter.emplace_back(new double[1 + i % 37]);
  const auto [b, b_first, b_second] = solveMarginalizeSolve(nullptr);
  expectSameStateBitForBit(*a, *b);
  EXPECT_EQ(a_first, b_first);
  EXPECT_EQ(a_second, b_second);
}

// The same solves with the evaluation on compute threads (task_pool.hpp: each pair's sum in
// one task, the points' and the cost's sums in residual order afterwards) come out bit for
// bit equal to the solves on the calling thread alone, for 2 and 3 threads — the native
// marginalisation of keyframe 2's points between them linearising on the threads too.
TEST(WindowSolverDeterminism, SolvesBitForBitIndependentlyOfTheComputeThreads) {
  const auto [a, a_first, a_second] = solveMarginalizeSolve(nullptr);
  for (int threads : {2, 3}) {
    TaskPool pool(threads);
    const auto [b, b_first, b_second] = solveMarginalizeSolve(&pool);
    expectSameStateBitForBit(*a, *b);
    EXPECT_EQ(a_first, b_first) << threads << " threads";
    EXPECT_EQ(a_second, b_second) << threads << " threads";
  }
}

// optimizeCoarseToFine with the native solver: the coarser level on Ceres, level 0 native;
// the perturbed window's cost comes down and the result is usable.
TEST(WindowSolverCoarseToFine, SolvesLevelZeroNatively) {
  auto window = perturbedWindow(testCamera(), testScene(), solverOptions(true, true, 4),
                                kNumKeyframes);
  const WindowSolveSummary summary = window->optimizeCoarseToFine(2);
  EXPECT_TRUE(summary.usable) << summary.message;
  EXPECT_EQ(summary.linear_solver, "NATIVE_DENSE_SCHUR");  // the last level's
  const WindowSolveSummary again = window->optimize();
  EXPECT_LT(again.initial_cost, summary.initial_cost);
}

}  // namespace
}  // namespace omnidso
