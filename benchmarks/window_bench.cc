// One window optimisation (7 keyframes, ~2000 points, UCM 480×480) on rendered images:
// time per solve and per iteration, hand-derived against autodiff residuals, DSO's 6
// iterations against the odometry's 2 (with and without reusing evaluations,
// evaluation_reuse.hpp), Ceres against the native window solver (window_solver.hpp), and
// the share of the time spent evaluating residuals/Jacobians versus in the linear solver.
// Building the window and destroying it are outside the timed region.
#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <memory>
#include <omnidso/core/task_pool.hpp>
#include <omnidso/backend/sliding_window.hpp>

#include "benchmark_room.hpp"
#include <omnidso/synth/bearing_table.hpp>
#include <omnidso/synth/renderer.hpp>
#include <omnidso/synth/scene.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

namespace omnidso {
namespace {

struct WindowFixture : bench::BenchmarkRoom {
  std::vector<SE3d> poses;
  std::vector<std::shared_ptr<const ImagePyramid>> images;
  std::vector<std::tuple<int, Eigen::Vector2d, double>> points;  // host, pixel, inverse distance

  WindowFixture() {
    const Mask mask = validityMask(camera);
    for (int k = 0; k < 7; ++k) {
      Eigen::Matrix<double, 6, 1> xi;
      xi << 0.05 * k, 0.01 * k, 0.03 * k, 0.01 * k, 0.06 * k, 0.0;
      poses.push_back(start * SE3d::exp(xi));
      images.push_back(std::make_shared<const ImagePyramid>(render(poses.back()), 5));
      // ~300 points per keyframe: the strongest gradient of each 16×16 cell.
      const ImageGradients& g = images.back()->gradients(0);
      for (int v0 = 8; v0 + 16 < 472; v0 += 16)
        for (int u0 = 8; u0 + 16 < 472; u0 += 16) {
          float best = 25.f;
          Eigen::Vector2d arg(-1, -1);
          for (int v = v0; v < v0 + 16; ++v)
            for (int u = u0; u < u0 + 16; ++u) {
              const float m = std::hypot(g.dx(u, v), g.dy(u, v));
              if (mask(u, v) && m > best) {
                best = m;
                arg = Eigen::Vector2d(u, v);
              }
            }
          Eigen::Vector3d bearing;
          synth::RayHit hit;
          if (arg.x() < 0 || !camera.unproject(arg, bearing)) continue;
          const Eigen::Vector3d dir = poses.back().rotation() * bearing;
          if (scene.intersect(poses.back().translation().cast<float>(), dir.cast<float>(), &hit))
            points.emplace_back(k, arg, 1.0 / hit.distance);
        }
    }
  }
};

const WindowFixture& fixture() {
  static const WindowFixture f;
  return f;
}

// The fixture's 7 keyframes and up to 2000 of its points, distances 5 % off.
std::unique_ptr<SlidingWindow> makeWindow(const WindowFixture& f, const WindowOptions& options) {
  auto window = std::make_unique<SlidingWindow>(f.camera.modelName(), f.camera.params(), options);
  for (int k = 0; k < 7; ++k)
    window->addKeyframe(k, 0.05 * k, 1.0, f.poses[k], Eigen::Vector2d::Zero(), f.images[k]);
  int added = 0;
  for (const auto& [host, pixel, d] : f.points)
    if (added < 2000 && window->addPoint(host, pixel, d * 1.05) >= 0) ++added;
  return window;
}

// The window's parameter values, to solve the same problem again (a warm solve).
struct WindowValues {
  std::vector<std::array<double, 7>> poses;
  std::vector<std::array<double, 2>> affines;
  std::vector<double> inverse_distances;
  Eigen::VectorXd intrinsics;

  explicit WindowValues(const SlidingWindow& w) : intrinsics(w.intrinsics()) {
    for (int id : w.keyframeIds()) {
      poses.push_back(w.keyframe(id).pose);
      affines.push_back(w.keyframe(id).affine);
    }
    for (const auto& [id, point] : w.points()) inverse_distances.push_back(point->inverse_distance);
  }
  void restore(SlidingWindow& w) const {
    size_t k = 0, p = 0;
    for (int id : w.keyframeIds()) {
      w.mutableKeyframe(id).pose = poses[k];
      w.mutableKeyframe(id).affine = affines[k++];
    }
    for (const auto& [id, point] : w.points()) w.mutablePoint(id).inverse_distance = inverse_distances[p++];
    w.mutableIntrinsics() = intrinsics;
  }
};

// warm: the timed solve is the window's second of the same problem (solved once untimed,
// the values restored), as in the odometry, where the window keeps its solver's buffers
// from keyframe to keyframe; cold: the window's first solve.
void BM_WindowOptimization(benchmark::State& state, DifferentiationMode mode, int max_iterations,
                           bool reuse_evaluations, bool native_solver, int compute_threads = 1,
                           bool warm = false) {
  const WindowFixture& f = fixture();
  TaskPool pool(compute_threads);
  double iterations = 0, eval_ms = 0, linear_ms = 0, solve_ms = 0;
  int solves = 0, num_points = 0, num_residuals = 0;
  for (auto _ : state) {
    state.PauseTiming();
    WindowOptions options;
    options.max_keyframes = 7;
    options.differentiation = mode;
    options.max_iterations = max_iterations;
    options.reuse_evaluations = reuse_evaluations;
    options.native_solver = native_solver;
    auto window = makeWindow(f, options);
    window->setTaskPool(&pool);
    num_points = window->numPoints();
    num_residuals = window->numResiduals();
    if (warm) {
      const WindowValues start(*window);
      window->optimize();
      start.restore(*window);
    }
    state.ResumeTiming();
    const WindowSolveSummary s = window->optimize();
    state.PauseTiming();
    window.reset();
    iterations += s.iterations;
    eval_ms += s.evaluation_ms;
    linear_ms += s.linear_solver_ms;
    solve_ms += s.solve_ms;
    ++solves;
    state.ResumeTiming();
  }
  state.counters["points"] = num_points;
  state.counters["residuals"] = num_residuals;
  state.counters["iterations"] = iterations / solves;
  state.counters["ms_per_iteration"] = solve_ms / std::max(1.0, iterations);
  state.counters["evaluation_share"] = eval_ms / solve_ms;
  state.counters["linear_solver_share"] = linear_ms / solve_ms;
}

// DSO's budget per keyframe: 6 iterations.
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Analytic, DifferentiationMode::kAnalytic, 6, true,
                  false)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Autodiff, DifferentiationMode::kAutodiff, 6, true,
                  false)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);
// The odometry's default (WindowOptions::max_iterations).
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Analytic_2it, DifferentiationMode::kAnalytic, 2,
                  true, false)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Analytic_2it_no_reuse,
                  DifferentiationMode::kAnalytic, 2, false, false)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
// The native window solver on the same problem (the same analytic residual kernel).
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Native, DifferentiationMode::kAnalytic, 6, true, true)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Native_2it, DifferentiationMode::kAnalytic, 2, true,
                  true)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
// … with the evaluation on two compute threads (task_pool.hpp; the same result), and both
// as the odometry solves: the window's second solve, its buffers kept.
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Native_2it_2threads, DifferentiationMode::kAnalytic,
                  2, true, true, 2)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Native_2it_warm, DifferentiationMode::kAnalytic, 2,
                  true, true, 1, true)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);
BENCHMARK_CAPTURE(BM_WindowOptimization, ucm_Native_2it_2threads_warm,
                  DifferentiationMode::kAnalytic, 2, true, true, 2, true)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

// Marginalising the oldest keyframe of that window after its 2-iteration solve (the
// odometry's step, sliding_window_marginalization.cc): its points and those the two newest
// keyframes do not observe go into the prior, then its pose and affine blocks.
void BM_MarginalizeOldestKeyframe(benchmark::State& state) {
  const WindowFixture& f = fixture();
  int marginalized_points = 0;
  for (auto _ : state) {
    state.PauseTiming();
    WindowOptions options;
    options.max_keyframes = 7;
    options.max_iterations = 2;
    auto window = makeWindow(f, options);
    window->optimize();
    const int points_before = window->numPoints();
    state.ResumeTiming();
    window->marginalizeKeyframe(0);
    state.PauseTiming();
    marginalized_points = points_before - window->numPoints();
    window.reset();
    state.ResumeTiming();
  }
  state.counters["points_out"] = marginalized_points;
}
BENCHMARK(BM_MarginalizeOldestKeyframe)->Unit(benchmark::kMillisecond)->Iterations(10);

}  // namespace
}  // namespace omnidso
