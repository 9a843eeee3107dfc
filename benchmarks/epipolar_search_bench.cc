// The epipolar-curve search (traceImmaturePoint) of one keyframe's candidates in one tracked
// frame, on the rendered 480×480 UCM room: DSO's 2000 candidates of a keyframe, traced into
// a frame 5 cm further along the camera's optical axis and turned by 1°. The odometry runs it
// for every candidate of every window keyframe in every frame (docs/performance.md, "Speed").
//   BM_TraceNewCandidates: first traces, interval [0, ∞): the whole walk of up to
//     max_search_px one-pixel steps, then the Gauss–Newton refinement.
//   BM_TraceRefinedCandidates: second traces after a first one from another frame: the
//     intervals are a few pixels long, as for most candidates of an older keyframe.
#include <benchmark/benchmark.h>

#include <omnidso/frontend/epipolar_search.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "benchmark_room.hpp"

namespace omnidso {
namespace {

struct SearchScene {
  bench::BenchmarkRoom room;
  ImagePyramid host, first, second;
  SE3d T_first_host, T_second_host;
  std::vector<ImmaturePoint> fresh;

  static SE3d moved(const SE3d& start, double forward_m, double yaw_rad) {
    Eigen::Matrix<double, 6, 1> xi;
    xi << 0, 0, forward_m, 0, yaw_rad, 0;  // camera frame: z forward, turn about y
    return start * SE3d::exp(xi);
  }

  SearchScene()
      : host(room.render(room.start), 4),
        first(room.render(moved(room.start, 0.05, 0.0175)), 4),
        second(room.render(moved(room.start, 0.10, 0.035)), 4) {
    T_first_host = moved(room.start, 0.05, 0.0175).inverse() * room.start;
    T_second_host = moved(room.start, 0.10, 0.035).inverse() * room.start;
    const Mask mask = validityMask(room.camera);
    for (const SelectedPixel& p : selectPixels(host, mask, PixelSelectorOptions{})) {
      ImmaturePoint point;
      if (makeImmaturePoint(room.camera, host.level(0), host.gradients(0), 0,
                            p.pixel.cast<double>(), &point))
        fresh.push_back(point);
    }
  }

  void trace(std::vector<ImmaturePoint>& points, const SE3d& T, const ImagePyramid& target,
             int* good) const {
    for (ImmaturePoint& p : points) {
      const TraceResult r = traceImmaturePoint(p, room.camera, T, target.level(0),
                                               target.gradients(0), AffineTransfer{},
                                               EpipolarSearchOptions{}, target.content(0));
      *good += r.status == TraceStatus::kGood;
    }
  }
};

const SearchScene& scene() {
  static const SearchScene s;
  return s;
}

void BM_TraceNewCandidates(benchmark::State& state) {
  const SearchScene& s = scene();
  int good = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<ImmaturePoint> points = s.fresh;
    good = 0;
    state.ResumeTiming();
    s.trace(points, s.T_first_host, s.first, &good);
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["candidates"] = static_cast<double>(s.fresh.size());
  state.counters["good"] = good;
}
BENCHMARK(BM_TraceNewCandidates)->Unit(benchmark::kMillisecond);

void BM_TraceRefinedCandidates(benchmark::State& state) {
  const SearchScene& s = scene();
  std::vector<ImmaturePoint> refined = s.fresh;
  int good = 0;
  s.trace(refined, s.T_first_host, s.first, &good);
  for (auto _ : state) {
    state.PauseTiming();
    std::vector<ImmaturePoint> points = refined;
    good = 0;
    state.ResumeTiming();
    s.trace(points, s.T_second_host, s.second, &good);
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["candidates"] = static_cast<double>(refined.size());
  state.counters["good"] = good;
}
BENCHMARK(BM_TraceRefinedCandidates)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace omnidso
