// One coarse-to-fine track() (coarse_tracker.hpp) of a rendered frame against its reference
// keyframe (UCM 480×480, ~2000 points with true distances, 5 levels), Ceres against the
// native tracker solver (tracker_solver.hpp) on the same problem:
//  - predicted: DSO's hypothesis list around a constant-velocity guess 0.5° and 5 mm off,
//    with the previous frame's error known, so trying stops after the first good hypothesis
//    (the odometry's common case);
//  - all_hypotheses: no previous error, so all 31 hypotheses are tried (each stopped after
//    the coarsest level when its error is far above the best): a tracker that is lost.
// The reference is set outside the timed region.
// And the narrow view's check of that reference (reference_depth_consistency.hpp, K = 8,
// τ 0.1), which `omnidso run` applies once per keyframe on views under 115°.
#include <benchmark/benchmark.h>

#include <limits>
#include <omnidso/frontend/coarse_tracker.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/frontend/reference_depth_consistency.hpp>

#include "benchmark_room.hpp"

namespace omnidso {
namespace {

struct TrackerFixture : bench::BenchmarkRoom {
  std::shared_ptr<const ImagePyramid> reference;
  std::unique_ptr<ImagePyramid> frame;
  std::vector<TrackingReferencePoint> points;
  SE3d truth;  // T_frame_ref

  TrackerFixture() {
    Eigen::Matrix<double, 6, 1> xi;
    xi << 0.04, -0.01, 0.03, 0.01, 0.03, -0.005;
    const SE3d frame_pose = start * SE3d::exp(xi);
    reference = std::make_shared<const ImagePyramid>(render(start), 5);
    frame = std::make_unique<ImagePyramid>(render(frame_pose), 5);
    truth = frame_pose.inverse() * start;
    PixelSelectorOptions selection;
    selection.desired_points = 2000;
    for (const SelectedPixel& p : selectPixels(*reference, validityMask(camera), selection)) {
      Eigen::Vector3d bearing;
      synth::RayHit hit;
      if (!camera.unproject(p.pixel.cast<double>(), bearing)) continue;
      const Eigen::Vector3d dir = start.rotation() * bearing;
      if (scene.intersect(start.translation().cast<float>(), dir.cast<float>(), &hit))
        points.push_back({p.pixel.cast<double>(), 1.0 / hit.distance});
    }
  }
};

const TrackerFixture& fixture() {
  static const TrackerFixture f;
  return f;
}

void BM_Track(benchmark::State& state, bool native_solver, bool previous_error_known) {
  const TrackerFixture& f = fixture();
  CoarseTrackerOptions options;
  options.native_solver = native_solver;
  CoarseTracker tracker(f.camera, options);
  tracker.setReference(f.reference, 1.0, Eigen::Vector2d::Zero(), f.points);
  // The constant-velocity guess: the truth, off by 0.5° and 5 mm.
  Eigen::Matrix<double, 6, 1> off;
  off << 0.005, 0.0, -0.002, 0.0, 0.5 * M_PI / 180.0, 0.003;
  const std::vector<SE3d> hypotheses = tracker.makeHypotheses(SE3d(), f.truth * SE3d::exp(off));
  const double infinity = std::numeric_limits<double>::infinity();
  const double previous_rmse =
      previous_error_known
          ? tracker.track(*f.frame, 1.0, hypotheses, Eigen::Vector2d::Zero(), infinity).rmse
          : infinity;
  TrackingResult result;
  for (auto _ : state) {
    result = tracker.track(*f.frame, 1.0, hypotheses, Eigen::Vector2d::Zero(), previous_rmse);
    benchmark::DoNotOptimize(result);
  }
  const SE3d error = result.T_frame_ref.inverse() * f.truth;
  state.counters["points"] = tracker.numReferencePoints(0);
  state.counters["hypotheses"] = result.hypotheses_tried;
  state.counters["rmse"] = result.rmse;
  state.counters["error_mm"] = 1e3 * error.translation().norm();
}

BENCHMARK_CAPTURE(BM_Track, predicted_Ceres, false, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Track, predicted_Native, true, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Track, all_hypotheses_Ceres, false, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Track, all_hypotheses_Native, true, false)->Unit(benchmark::kMillisecond);

void BM_KeepConsistentDepths(benchmark::State& state) {
  const TrackerFixture& f = fixture();
  ReferenceDepthConsistencyOptions options;
  options.neighbours = 8;
  size_t kept = 0;
  for (auto _ : state) {
    std::vector<TrackingReferencePoint> points = f.points;  // the copy the odometry hands over
    kept = keepConsistentDepths(std::move(points), options).size();
    benchmark::DoNotOptimize(kept);
  }
  state.counters["points"] = static_cast<double>(f.points.size());
  state.counters["kept"] = static_cast<double>(kept);
}

BENCHMARK(BM_KeepConsistentDepths)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace omnidso
