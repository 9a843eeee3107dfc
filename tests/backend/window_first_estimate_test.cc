// First-estimate Jacobians in the native window solve (evaluateWindow's `first_estimate`,
// WindowOptions::first_estimate_jacobians). The photometric residuals depend on the frames'
// translations and the points' inverse distances only through their product, so scaling every
// translation about a fixed centre by (1 + ε) and every inverse distance by 1 / (1 + ε) leaves
// them unchanged: J v = 0 for that direction v, taken at the point where J is evaluated. A
// prior built at the frames' first estimates x̄ has the direction at x̄ in its null space; the
// window's residuals must have the same one, so their Jacobians must be taken at x̄ too. Taken
// at the current x, once x has moved from x̄, they see a scale change along v(x̄) — the prior
// and the residuals then disagree about the scale (docs/performance.md, "First-estimate
// Jacobians in the window").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_objective.hpp>

#include "window_test_scenes.hpp"

namespace omnidso {
namespace {

constexpr int kNumKeyframes = 4;

// vᵀ H v = ‖J v‖² from the window's normal equations: frames (pose [ρ; φ], affine) and
// intrinsics in frame space, and one inverse distance per point.
double quadraticForm(const WindowNormalEquations& eq, const Eigen::VectorXd& v_frames,
                     const Eigen::VectorXd& v_points) {
  double q = v_frames.dot(eq.frameHessian() * v_frames);
  q += 2.0 * v_points.dot(eq.pointCoupling() * v_frames);
  q += v_points.dot(eq.pointHessian().cwiseProduct(v_points));
  return q;
}

// The scale direction at the frames' values in `problem`: the translation part ρ_i = R_iᵀ
// (t_i − c) of every variable pose, c the first frame's centre (the gauge holds that frame's
// pose constant), and −ρ_p for every point.
void scaleDirection(const WindowProblem& problem, Eigen::VectorXd* v_frames,
                    Eigen::VectorXd* v_points) {
  v_frames->setZero(problem.frameSpaceSize());
  const SE3d first = SE3d::fromParameters(problem.frames.front().pose);
  for (size_t i = 0; i < problem.frames.size(); ++i) {
    const WindowFrame& frame = problem.frames[i];
    if (frame.pose_constant) continue;
    const SE3d T = SE3d::fromParameters(frame.pose);
    v_frames->segment<3>(kFrameTangentSize * static_cast<int>(i)) =
        T.rotationMatrix().transpose() * (T.translation() - first.translation());
  }
  v_points->resize(static_cast<int>(problem.points.size()));
  for (size_t p = 0; p < problem.points.size(); ++p)
    (*v_points)[static_cast<int>(p)] = problem.points[p].constant ? 0.0 : -*problem.points[p].inverse_distance;
}

// The perturbed sweep window of the tests, solved natively.
std::unique_ptr<SlidingWindow> nativeTestWindow() {
  WindowOptions options = test::recoveryOptions(kNumKeyframes, true);
  options.native_solver = true;
  return test::perturbedWindow(test::sweepCamera(), test::sweepScene(kNumKeyframes), options,
                               kNumKeyframes);
}

TEST(WindowFirstEstimate, TheResidualsShareTheFirstEstimatesScaleNullSpace) {
  auto window = nativeTestWindow();
  const std::optional<WindowProblem> current = window->nativeProblem();
  ASSERT_TRUE(current.has_value());
  ASSERT_TRUE(current->frames.front().pose_constant);

  // x̄: every variable frame's translation 20 % longer from the first frame and turned by 1°,
  // the points as they are (a point never enters a prior before it is marginalised).
  WindowProblem first_estimate = *current;
  std::vector<std::array<double, 7>> x_bar(current->frames.size());
  const SE3d first = SE3d::fromParameters(current->frames.front().pose);
  for (size_t i = 0; i < current->frames.size(); ++i) {
    if (current->frames[i].pose_constant) continue;
    const SE3d T = SE3d::fromParameters(current->frames[i].pose);
    Eigen::Matrix<double, 6, 1> turn;
    turn << 0, 0, 0, 0.0, std::acos(-1.0) / 180.0, 0.0;
    const SE3d moved(T.rotation(), first.translation() + 1.2 * (T.translation() - first.translation()));
    (moved * SE3d::exp(turn)).toParameters(x_bar[i].data());
    first_estimate.frames[i].pose = x_bar[i].data();
  }

  Eigen::VectorXd v_frames, v_points;
  scaleDirection(first_estimate, &v_frames, &v_points);
  // A direction of the same size for scale: the point part alone (each inverse distance's
  // own Jacobian, which no translation offsets).
  const Eigen::VectorXd no_frames = Eigen::VectorXd::Zero(v_frames.size());

  WindowNormalEquations at_first_estimate, at_current;
  WindowCost cost_first_estimate, cost_current;
  ASSERT_TRUE(evaluateWindow(*current, &at_first_estimate, &cost_first_estimate, nullptr, &first_estimate));
  ASSERT_TRUE(evaluateWindow(*current, &at_current, &cost_current));
  // The cost is the current estimate's either way.
  EXPECT_EQ(cost_first_estimate.variable, cost_current.variable);

  const double reference = quadraticForm(at_first_estimate, no_frames, v_points);
  const double with_first_estimate = quadraticForm(at_first_estimate, v_frames, v_points);
  const double with_current = quadraticForm(at_current, v_frames, v_points);
  std::cout << "‖J v(x̄)‖² / ‖J_ρ ρ‖²: Jacobians at x̄ " << std::scientific << with_first_estimate / reference
            << ", at x " << with_current / reference << "\n";
  ASSERT_GT(reference, 0.0);
  // Exact up to rounding (and the bilinear interpolation's piecewise gradient, which both
  // evaluations share): 1e-6 of the point part's own size.
  EXPECT_LT(with_first_estimate, 1e-6 * reference);
  // At x the direction of x̄ is no null direction: the translations differ by 20 %.
  EXPECT_GT(with_current, 1e-3 * reference);
}

// DSO's first-estimate Jacobians (Engel et al. 2018, sec. 2.3) take the geometric factors
// ∂π/∂x̃ ∂x̃/∂ξ at x̄ but the image gradient ∇I at the current estimate x, where the residual
// is: the image is not smooth on the scale of how far a projection moves from x̄ to x. With
// every variable frame turned by 0.5° at x̄ (3 px on this 320-pixel fisheye image, whose
// 1-pixel blur decorrelates the gradient within about 2 px) the Jacobians at x̄ must stay
// those at x up to the geometric factors' change, O(0.5°) relative; sampled at x̄'s
// projections instead, ∇I belongs to other pixels.
TEST(WindowFirstEstimate, TheImageGradientIsTakenAtTheCurrentEstimate) {
  auto window = nativeTestWindow();
  const std::optional<WindowProblem> current = window->nativeProblem();
  ASSERT_TRUE(current.has_value());

  WindowProblem first_estimate = *current;
  std::vector<std::array<double, 7>> x_bar(current->frames.size());
  for (size_t i = 0; i < current->frames.size(); ++i) {
    if (current->frames[i].pose_constant) continue;
    Eigen::Matrix<double, 6, 1> turn;
    turn << 0, 0, 0, 0.0, 0.5 * std::acos(-1.0) / 180.0, 0.0;
    (SE3d::fromParameters(current->frames[i].pose) * SE3d::exp(turn)).toParameters(x_bar[i].data());
    first_estimate.frames[i].pose = x_bar[i].data();
  }
  WindowNormalEquations at_first_estimate, at_current;
  WindowCost cost_first_estimate, cost_current;
  ASSERT_TRUE(evaluateWindow(*current, &at_first_estimate, &cost_first_estimate, nullptr, &first_estimate));
  ASSERT_TRUE(evaluateWindow(*current, &at_current, &cost_current));

  // The variable frames' pose blocks of JᵀJ and the points' ∂r/∂d information.
  const Eigen::MatrixXd& H_x_bar = at_first_estimate.frameHessian();
  const Eigen::MatrixXd& H_x = at_current.frameHessian();
  ASSERT_GT(H_x.norm(), 0.0);
  const double frames_change = (H_x_bar - H_x).norm() / H_x.norm();
  const double points_change =
      (at_first_estimate.pointHessian() - at_current.pointHessian()).norm() / at_current.pointHessian().norm();
  std::cout << "relative change of JᵀJ from x to x̄: frames " << frames_change << ", points "
            << points_change << "\n";
  EXPECT_LT(frames_change, 0.1);
  EXPECT_LT(points_change, 0.1);
}

// The window's solve: before any prior holds a frame the option changes nothing, bit for bit
// (x̄ = x); once a keyframe is marginalised and the newest keyframe moved from its first
// estimate, the frames the prior holds are linearised at x̄ and the solve differs.
TEST(WindowFirstEstimate, TheSolveLinearisesAtTheFirstEstimatesOnceAPriorHoldsThem) {
  auto solved = [](bool first_estimate_jacobians, bool marginalise) {
    WindowOptions options = test::recoveryOptions(kNumKeyframes, true);
    options.native_solver = true;
    options.max_iterations = 3;
    options.first_estimate_jacobians = first_estimate_jacobians;
    auto window = test::perturbedWindow(test::sweepCamera(), test::sweepScene(kNumKeyframes),
                                        options, kNumKeyframes);
    window->optimize();
    if (marginalise) {
      window->marginalizeKeyframe(window->keyframeIds().front());
      EXPECT_TRUE(window->hasPrior());
      WindowKeyframe& kf = window->mutableKeyframe(window->keyframeIds().back());
      test::moveInCamera(kf.T_world_cam(), Eigen::Vector3d(0.01, 0, 0), Eigen::Vector3d(0.5, 0, 0))
          .toParameters(kf.pose.data());
      window->optimize();
    }
    std::vector<double> translations;
    for (int id : window->keyframeIds()) {
      const Eigen::Vector3d t = window->keyframe(id).T_world_cam().translation();
      translations.insert(translations.end(), t.data(), t.data() + 3);
    }
    return translations;
  };
  EXPECT_EQ(solved(true, false), solved(false, false));
  const std::vector<double> with = solved(true, true), without = solved(false, true);
  ASSERT_EQ(with.size(), without.size());
  double difference = 0.0;
  for (size_t i = 0; i < with.size(); ++i)
    difference = std::max(difference, std::abs(with[i] - without[i]));
  std::cout << "largest translation difference after a marginalisation: " << difference << "\n";
  EXPECT_GT(difference, 1e-9);
}

}  // namespace
}  // namespace omnidso
