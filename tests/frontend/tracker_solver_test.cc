// The native tracker solver (tracker_solver.hpp): on rendered fisheye pairs it gives the
// Ceres path's result at every level — both minimise the same cost by the same
// Levenberg–Marquardt steps, so they may differ only by the rounding of the 8×8 step
// (≈ κ · 1e-16 relative, κ the condition number of the Jacobi-scaled system, ≲ 1e6 here):
// far below 1e-6 — and the same iteration count; tracking converges to the true pose; and on
// tiny one-dimensional problems its cost, Huber weighting, affine prior and handling of
// invalid residuals are those computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <omnidso/frontend/coarse_tracker.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/frontend/tracker_solver.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "support/rendered_scene.hpp"

namespace omnidso {
namespace {

double rotationDistance(const SE3d& a, const SE3d& b) {
  return so3Log((a.inverse() * b).rotation()).norm();
}

// A rendered UCM 185° pair: the reference pyramid with its points (true distances) and a
// frame moved by a few centimetres and degrees, brightened by `gain`, `offset`.
struct RenderedPair {
  Camera camera = synth::syntheticCamera("ucm", 185.0, 320, 320);
  test::RenderedScene scene{camera, 11};
  SE3d T_world_ref = scene.centralPose();
  SE3d T_world_frame = test::moveInCamera(T_world_ref, {0.03, -0.01, 0.02}, {1.0, 2.0, 0.5});
  std::shared_ptr<const ImagePyramid> reference = scene.renderPyramid(T_world_ref);
  std::vector<TrackingReferencePoint> points;

  RenderedPair() {
    PixelSelectorOptions selection;
    selection.desired_points = 1500;
    for (const SelectedPixel& p : selectPixels(*reference, validityMask(camera), selection)) {
      Eigen::Vector3d bearing;
      if (!camera.unproject(p.pixel.cast<double>(), bearing)) continue;
      const auto rho = scene.distance(T_world_ref, bearing);
      if (rho) points.push_back({p.pixel.cast<double>(), 1.0 / *rho});
    }
  }
  ImagePyramid frame(double gain = 1.0, double offset = 0.0) const {
    ImageF image = scene.render(T_world_frame);
    for (size_t i = 0; i < image.size(); ++i)
      image.data()[i] = static_cast<float>(gain * image.data()[i] + offset);
    return ImagePyramid(image, 5);
  }
  SE3d truth() const { return T_world_frame.inverse() * T_world_ref; }
};

const RenderedPair& renderedPair() {
  static const RenderedPair pair;
  return pair;
}

std::unique_ptr<CoarseTracker> makeTracker(bool native, double prior_weight,
                                           int max_iterations = 0) {
  CoarseTrackerOptions options;
  options.native_solver = native;
  if (max_iterations > 0) options.max_iterations = {max_iterations};
  options.affine_prior_weight_a = options.affine_prior_weight_b = prior_weight;
  auto tracker = std::make_unique<CoarseTracker>(renderedPair().camera, options);
  tracker->setReference(renderedPair().reference, 1.0, Eigen::Vector2d::Zero(),
                        renderedPair().points);
  return tracker;
}

// Per level, from starts around the truth: the calibrated case (the default affine prior)
// and a brightened frame with the affine free (the prior off), where [a, b] moves far; each
// solved to the end (the tracker's iteration limits) and for ONE iteration — the first
// step alone shows the damping (Jacobi scaling, D², Δ), which a converged solve forgets.
// Tolerance 1e-9: the rounding of the steps, ≈ κ · 1e-16 with κ ≲ 1e6, and 10× room.
TEST(TrackerSolverTest, AgreesWithCeresAtEachLevelFromPerturbedStarts) {
  const RenderedPair& pair = renderedPair();
  ASSERT_GT(pair.points.size(), 500u);
  struct Case {
    double prior_weight, gain, offset;
    int max_iterations;  // 0: the tracker's
  };
  int solves = 0, total_iterations = 0;
  double max_rotation = 0.0, max_translation = 0.0, max_affine = 0.0;
  for (const Case& c : {Case{1e8, 1.0, 0.0, 0}, Case{0.0, 1.15, -6.0, 0}, Case{1e8, 1.0, 0.0, 1},
                        Case{0.0, 1.15, -6.0, 1}}) {
    const auto ceres_tracker = makeTracker(false, c.prior_weight, c.max_iterations);
    const auto native_tracker = makeTracker(true, c.prior_weight, c.max_iterations);
    const ImagePyramid frame = pair.frame(c.gain, c.offset);
    for (int level = 0; level < 5; ++level)
      for (int k = 0; k < 3; ++k) {
        const double size = 0.4 * (level + 1) * (k + 1);  // degrees; centimetres / 2
        const SE3d start =
            test::moveInCamera(pair.truth(), 0.005 * size * Eigen::Vector3d(1, -1, 0.5),
                               size * Eigen::Vector3d(0.3, -1, 0.6));
        SE3d pose_ceres = start, pose_native = start;
        Eigen::Vector2d affine_ceres(0.02, 1.0), affine_native(0.02, 1.0);
        const TrackingLevelSolve a =
            ceres_tracker->solveLevel(frame, 1.0, level, &pose_ceres, &affine_ceres);
        const TrackingLevelSolve b =
            native_tracker->solveLevel(frame, 1.0, level, &pose_native, &affine_native);
        SCOPED_TRACE(testing::Message() << "prior " << c.prior_weight << " iterations "
                                        << c.max_iterations << " level " << level << " start "
                                        << k);
        ASSERT_GE(a.iterations, 1);  // a solve took place
        EXPECT_EQ(a.iterations, b.iterations);
        EXPECT_LT(rotationDistance(pose_ceres, pose_native), 1e-9);
        EXPECT_LT((pose_ceres.translation() - pose_native.translation()).norm(),
                  1e-9 * pose_ceres.translation().norm());
        EXPECT_NEAR(affine_ceres.x(), affine_native.x(), 1e-9);
        EXPECT_NEAR(affine_ceres.y(), affine_native.y(),
                    1e-9 * std::max(1.0, std::abs(affine_ceres.y())));
        EXPECT_NEAR(a.rmse, b.rmse, 1e-9 * a.rmse);
        EXPECT_EQ(a.valid_fraction, b.valid_fraction);
        // The solve did something: the pose moved, and a free affine too.
        EXPECT_GT(rotationDistance(start, pose_native) +
                      (start.translation() - pose_native.translation()).norm(),
                  1e-6);
        if (c.prior_weight == 0.0) {
          EXPECT_GT((affine_native - Eigen::Vector2d(0.02, 1.0)).norm(), 1e-3);
        }
        ++solves;
        total_iterations += b.iterations;
        max_rotation = std::max(max_rotation, rotationDistance(pose_ceres, pose_native));
        max_translation = std::max(
            max_translation, (pose_ceres.translation() - pose_native.translation()).norm() /
                                 pose_ceres.translation().norm());
        max_affine = std::max(max_affine, (affine_ceres - affine_native).cwiseAbs().maxCoeff());
      }
  }
  EXPECT_EQ(solves, 60);
  std::cout << solves << " solves, " << total_iterations << " iterations; largest differences: "
            << "rotation " << max_rotation << " rad, translation " << max_translation
            << " (relative), affine " << max_affine << "\n";
}

// track() with the native solver: from a start 1.5° and 1.5 cm off, the true pose (as
// coarse_tracker_test.cc demands of the Ceres path), and the same pose as Ceres's track().
TEST(TrackerSolverTest, NativeTrackingConvergesToTheTruePose) {
  const RenderedPair& pair = renderedPair();
  const ImagePyramid frame = pair.frame();
  double mean_inverse_distance = 0.0;
  for (const auto& p : pair.points)
    mean_inverse_distance += p.inverse_distance / static_cast<double>(pair.points.size());
  const SE3d start = test::moveInCamera(pair.truth(), {0.01, 0.01, -0.005}, {1.0, -1.0, 0.5});
  const auto track = [&](bool native) {
    return makeTracker(native, 1e8)->track(frame, 1.0, {start}, Eigen::Vector2d::Zero(),
                                          std::numeric_limits<double>::infinity());
  };
  const TrackingResult native = track(true), ceres = track(false);
  ASSERT_TRUE(native.ok);
  ASSERT_TRUE(ceres.ok);
  const SE3d error = native.T_frame_ref.inverse() * pair.truth();
  EXPECT_LT(error.translation().norm() * mean_inverse_distance, 1e-3);
  EXPECT_LT(rotationDistance(native.T_frame_ref, pair.truth()) * 180.0 / M_PI, 0.1);
  EXPECT_LT(rotationDistance(native.T_frame_ref, ceres.T_frame_ref), 1e-9);
  EXPECT_LT((native.T_frame_ref.translation() - ceres.T_frame_ref.translation()).norm(),
            1e-9 * ceres.T_frame_ref.translation().norm());
  EXPECT_NEAR(native.rmse, ceres.rmse, 1e-9 * ceres.rmse);
}

// Tiny problems in b alone: r_i = b − y_i (∂r/∂b = 1; the pose and a do not enter), each
// valid where `valid(i, b)` says so.
class OffsetResiduals final : public TrackerResiduals {
 public:
  OffsetResiduals(std::vector<double> y, std::function<bool(int, double)> valid)
      : y_(std::move(y)), valid_(std::move(valid)) {}
  int size() const override { return static_cast<int>(y_.size()); }
  void setPoint(const double*, const double* affine) override { b_ = affine[1]; }
  bool evaluate(int i, double* residual, double* jacobian) const override {
    if (!valid_(i, b_)) return false;
    *residual = b_ - y_[static_cast<size_t>(i)];
    if (jacobian) {
      std::fill_n(jacobian, 8, 0.0);
      jacobian[7] = 1.0;
    }
    return true;
  }

 private:
  std::vector<double> y_;
  std::function<bool(int, double)> valid_;
  double b_ = 0.0;
};

struct TinySolve {
  TrackerSolverSummary summary;
  double a, b;
};

TinySolve solveTiny(OffsetResiduals& residuals, double prior_a, double prior_b, double b0,
                    int max_iterations = 50) {
  TrackerProblem problem;
  problem.residuals = &residuals;
  problem.huber_threshold = 9.0;
  problem.invalid_residual = 12.0;
  problem.affine_prior_mean = Eigen::Vector2d(0.25, 0.0);
  problem.affine_prior_weight_a = prior_a;
  problem.affine_prior_weight_b = prior_b;
  problem.min_residuals = 2;
  TrackerSolverOptions options;
  options.max_num_iterations = max_iterations;
  // Run to the end: stop only once the cost no longer changes at all (|ΔE| ≤ 0) or the step
  // is below 1e-12. E resolves changes down to ~1e-13 (E ≈ 10³), so b is found to ~1e-7.
  options.function_tolerance = 0.0;
  options.parameter_tolerance = 1e-12;
  double pose[7] = {0, 0, 0, 1, 0, 0, 0};
  double affine[2] = {0.5, b0};
  const TrackerSolverSummary summary = solveTracker(problem, options, pose, affine);
  EXPECT_EQ(pose[3], 1.0);  // no residual moves the pose
  return {summary, affine[0], affine[1]};
}

// E at b = 1 with y = {0, 1, 2, 100}, k = 9, the prior ½·4·(0.5 − 0.25)² + ½·3·1²:
//   ½(1 + 0 + 1) + (9·99 − ½·81) + 0.125 + 1.5 = 1 + 850.5 + 1.625.
TEST(TrackerSolverTinyTest, CostIsHuberPlusPriorByHand) {
  OffsetResiduals residuals({0, 1, 2, 100}, [](int, double) { return true; });
  const TinySolve s = solveTiny(residuals, 4.0, 3.0, 1.0, 0);
  EXPECT_EQ(s.summary.num_residuals, 4);
  EXPECT_EQ(s.summary.iterations, 0);
  EXPECT_DOUBLE_EQ(s.summary.initial_cost, 1.0 + 850.5 + 1.625);
  EXPECT_EQ(s.b, 1.0);  // no iteration, no move
}

// The minimum of Σ ½ρ((b − y_i)²) + ½ w_b b²: Σ_inliers (b − y_i) − k + w_b b = 0 with the
// outlier 100 pulling by k = 9 only (Huber): b = (0 + 1 + 2 + 9) / (3 + w_b) — 4 without
// the prior, 2 with w_b = 3 (least squares would give 25.75 and 103/7). a is held at its
// prior mean 0.25 by w_a alone.
TEST(TrackerSolverTinyTest, HuberWeightingAndPriorGiveTheHandMinimum) {
  OffsetResiduals residuals({0, 1, 2, 100}, [](int, double) { return true; });
  const TinySolve free = solveTiny(residuals, 0.0, 0.0, 0.0);
  EXPECT_NE(free.summary.termination, TrackerTermination::kFailure);
  EXPECT_NEAR(free.b, 4.0, 1e-6);
  EXPECT_EQ(free.a, 0.5);  // a enters nothing: it stays
  const TinySolve prior = solveTiny(residuals, 4.0, 3.0, 0.0);
  EXPECT_NEAR(prior.b, 2.0, 1e-6);
  EXPECT_NEAR(prior.a, 0.25, 1e-6);
  // E(2) = ½(4 + 1 + 0) + (9·98 − 40.5) + ½·3·4.
  EXPECT_NEAR(prior.summary.final_cost, 2.5 + 841.5 + 6.0, 1e-9);
}

// Residual 4 cannot be evaluated at the start: left out (not penalised). Residual 3
// (y = 100) can only while b < 0.5: beyond, it costs the penalty's Huber energy
// ½(2·9·12 − 81) = 67.5 with a zero gradient, so the minimum is the mean of the rest, b = 1,
// E = 67.5 + ½(1 + 0 + 1) — not E = 1 (dropped) nor a rejected step (evaluation failure).
TEST(TrackerSolverTinyTest, InvalidResidualsLeftOutAtTheStartPenalisedAfter) {
  OffsetResiduals residuals({0, 1, 2, 100, -50}, [](int i, double b) {
    return i < 3 || (i == 3 && b < 0.5);
  });
  const TinySolve s = solveTiny(residuals, 0.0, 0.0, 0.0);
  EXPECT_EQ(s.summary.num_residuals, 4);
  // At b = 0: ½(0 + 1 + 4) + (9·100 − 40.5); residual 4 would add 9·50 − 40.5.
  EXPECT_DOUBLE_EQ(s.summary.initial_cost, 2.5 + 859.5);
  EXPECT_NEAR(s.b, 1.0, 1e-6);
  EXPECT_NEAR(s.summary.final_cost, 67.5 + 1.0, 1e-9);
}

// Fewer valid residuals than problem.min_residuals: nothing is solved, nothing moves.
TEST(TrackerSolverTinyTest, TooFewValidResidualsSolveNothing) {
  OffsetResiduals residuals({0, 1, 2}, [](int i, double) { return i == 0; });
  const TinySolve s = solveTiny(residuals, 0.0, 0.0, 5.0);
  EXPECT_EQ(s.summary.termination, TrackerTermination::kNotSolved);
  EXPECT_EQ(s.summary.num_residuals, 1);
  EXPECT_EQ(s.b, 5.0);
}

}  // namespace
}  // namespace omnidso
