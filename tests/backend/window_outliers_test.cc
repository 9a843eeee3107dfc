// The window's outlier pass after a native solve (sliding_window_outliers.cc): it takes the
// residuals' raw energies from the solve's last evaluation while the window is as the solve
// left it, and evaluates again once anything has changed. Oracle: Ceres's evaluation of each
// residual block (OutOfBoundsPenalty::rawEnergy) at the state the pass sees.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <set>
#include <omnidso/backend/outlier_threshold.hpp>
#include <omnidso/backend/window_solver.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>

#include "window_test_scenes.hpp"

namespace omnidso {
namespace {

using Residuals = std::set<std::pair<int, int>>;  // (point id, target keyframe id)

constexpr int kNumKeyframes = 4;

const Camera& testCamera() { return test::sweepCamera(); }

const test::WindowScene& testScene() { return test::sweepScene(kNumKeyframes); }

std::unique_ptr<SlidingWindow> solvedWindow(const WindowOptions& options) {
  auto window = test::perturbedWindow(testCamera(), testScene(), options, kNumKeyframes);
  window->optimize();
  return window;
}

WindowOptions nativeOptions() {
  WindowOptions options = test::recoveryOptions(kNumKeyframes, true);
  options.max_iterations = 2;
  options.native_solver = true;
  return options;
}

// What the pass must leave: residuals whose Ceres raw energy is within the bound, of points
// left with enough of them. `twin` is a copy of the window the pass runs on, built and edited
// the same way: Ceres evaluates its residual blocks, which mutableProblem() adds to its
// problem, while the window under test keeps its blocks deferred (sliding_window.hpp), so
// that its pass evaluates deferred residuals itself.
// `bound_of(host id, target id)` is the bound a residual must stay within.
template <typename BoundOf>
Residuals expectedAfterPass(SlidingWindow& twin, const WindowOptions& options,
                            const BoundOf& bound_of, int* num_removed) {
  Residuals kept;
  *num_removed = 0;
  const ceres::Problem& problem = twin.mutableProblem();
  for (const auto& [pid, point] : twin.points()) {
    Residuals of_point;
    for (const auto& [target, id] : point->residuals) {
      const double energy = rawEnergy(problem, id);
      const double bound = bound_of(point->host_id, target);
      // The pass's energies agree with these to rounding (above): none may sit on the bound.
      EXPECT_GT(std::abs(energy - bound), 1e-9 * bound);
      if (energy <= bound)
        of_point.insert({pid, target});
      else
        ++*num_removed;
    }
    if (static_cast<int>(of_point.size()) >= options.min_residuals_per_point)
      kept.insert(of_point.begin(), of_point.end());
  }
  return kept;
}

Residuals expectedAfterPass(SlidingWindow& twin, const WindowOptions& options,
                            int* num_removed) {
  const double bound = options.outlier_energy_per_pixel * kWindowPatternSize;
  return expectedAfterPass(twin, options, [bound](int, int) { return bound; }, num_removed);
}

Residuals residualsOf(const SlidingWindow& window) {
  Residuals out;
  for (const auto& [pid, point] : window.points())
    for (const auto& [target, id] : point->residuals) out.insert({pid, target});
  return out;
}

// The solver's energies are Ceres's raw energies at the values it returns, to rounding: the
// same kernel, but the native solver unprojects each host pattern once per point and sums in
// its own order (1e-9 relative: 10⁴ × the rounding of a few hundred operations).
TEST(WindowOutliers, SolverReturnsCeresRawEnergies) {
  auto window = test::perturbedWindow(testCamera(), testScene(), nativeOptions(), kNumKeyframes);
  const std::optional<WindowProblem> native = window->nativeProblem();
  ASSERT_TRUE(native.has_value());
  WindowSolverOptions options;
  options.max_num_iterations = 2;
  const WindowSolverSummary s = solveWindow(*native, options);
  ASSERT_TRUE(s.usable()) << s.message;
  ASSERT_EQ(s.residual_energies.size(), native->residuals.size());
  size_t k = 0;
  int invalid = 0;
  const ceres::Problem& problem = window->mutableProblem();
  for (const auto& [pid, point] : window->points())
    for (const auto& [target, id] : point->residuals) {
      const double ceres = rawEnergy(problem, id);
      if (std::isinf(ceres)) {
        EXPECT_TRUE(std::isinf(s.residual_energies[k])) << "point " << pid << ", target " << target;
        ++invalid;
      } else {
        EXPECT_NEAR(s.residual_energies[k], ceres, 1e-9 * ceres) << "point " << pid << ", target " << target;
      }
      ++k;
    }
  std::cout << k << " residuals, " << invalid << " invalid\n";
}

// Right after the solve: the pass removes exactly what Ceres's energies say. The rendered
// window has no outliers at DSO's bound (12² per pixel), so the bound is lowered to 5 per
// pixel, inside the spread of the residuals' energies, to make the pass remove some.
TEST(WindowOutliers, PassAfterANativeSolveRemovesWhatCeresEnergiesSay) {
  WindowOptions options = nativeOptions();
  options.outlier_energy_per_pixel = 5.0;
  auto window = solvedWindow(options), twin = solvedWindow(options);
  int num_removed = 0;
  const Residuals expected = expectedAfterPass(*twin, options, &num_removed);
  EXPECT_GT(num_removed, 20);
  EXPECT_LT(num_removed, window->numResiduals() / 2);
  EXPECT_EQ(window->removeOutliers(), num_removed);
  EXPECT_EQ(residualsOf(*window), expected);
}

// After an edit the solve's energies are stale: turning the newest keyframe by 60° takes
// many of its observations out of the image, and the pass must see that.
TEST(WindowOutliers, PassAfterAnEditEvaluatesAgain) {
  const WindowOptions options = nativeOptions();
  auto window = solvedWindow(options), twin = solvedWindow(options);
  for (SlidingWindow* w : {window.get(), twin.get()}) {
    WindowKeyframe& kf = w->mutableKeyframe(w->keyframeIds().back());
    test::moveInCamera(kf.T_world_cam(), Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 60, 0))
        .toParameters(kf.pose.data());
  }
  int num_removed = 0;
  const Residuals expected = expectedAfterPass(*twin, options, &num_removed);
  ASSERT_GT(num_removed, 20) << "the edit should invalidate many residuals";
  EXPECT_EQ(window->removeOutliers(), num_removed);
  EXPECT_EQ(residualsOf(*window), expected);
}

// The adaptive bound (outlier_threshold.hpp): the pass measures the newest keyframe's θ from
// the energies of the residuals it observes, and removes a residual above the larger θ of its
// host and target; between keyframes that have none, the fixed bound holds. The options are
// chosen so that θ falls inside the spread of the newest keyframe's energies (without the
// fixed part and with f = 1, θ = e_(0.7) / 4: a quarter of the 70 % quantile), and the
// fixed bound is left at DSO's 12² per pixel, which removes nothing here (above).
TEST(WindowOutliers, AdaptiveBoundIsMeasuredOnTheNewestKeyframesResiduals) {
  WindowOptions options = nativeOptions();
  options.outlier_threshold.adaptive = true;
  options.outlier_threshold.quantile_factor = 1.0;
  options.outlier_threshold.fixed_energy_per_pixel = 0.0;
  auto window = solvedWindow(options), twin = solvedWindow(options);
  const int newest = twin->keyframeIds().back();
  std::vector<double> observed;
  const ceres::Problem& problem = twin->mutableProblem();
  for (const auto& [pid, point] : twin->points())
    for (const auto& [target, id] : point->residuals)
      if (target == newest) observed.push_back(rawEnergy(problem, id));
  const double theta = keyframeOutlierEnergy(observed, kWindowPatternSize, options.outlier_threshold);
  ASSERT_GT(theta, 0.0);
  const double fixed = options.outlier_energy_per_pixel * kWindowPatternSize;
  const auto bound_of = [&](int host, int target) {
    return host == newest || target == newest ? theta : fixed;
  };
  int num_removed = 0;
  const Residuals expected = expectedAfterPass(*twin, options, bound_of, &num_removed);
  EXPECT_GT(num_removed, 20);
  EXPECT_EQ(window->removeOutliers(), num_removed);
  EXPECT_EQ(residualsOf(*window), expected);
  EXPECT_NEAR(window->keyframe(newest).outlier_energy, theta, 1e-9 * theta);
  for (int id : window->keyframeIds()) {
    if (id == newest) continue;
    EXPECT_EQ(window->keyframe(id).outlier_energy, 0.0) << "keyframe " << id;
  }
}

}  // namespace
}  // namespace omnidso
