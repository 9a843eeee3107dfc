// Candidate selection of one keyframe (selectPixels, DSO's 2000 candidates) on a rendered
// 480×480 UCM room image with the camera's validity mask: the odometry runs it once per
// keyframe (docs/performance.md, "Speed").
//   BM_SelectPixels: the selection; BM_SelectPixelsReference: the implementation it replaced
//     (tests/support/reference_selection.hpp, the same output), for a side-by-side ratio.
#include <benchmark/benchmark.h>

#include <cmath>

#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "benchmark_room.hpp"
#include "support/reference_selection.hpp"

namespace omnidso {
namespace {

template <typename Select>
void runSelection(benchmark::State& state, const Select& select) {
  const bench::BenchmarkRoom room;
  const ImagePyramid pyramid(room.render(room.start), 4);
  const Mask mask = validityMask(room.camera);
  PixelSelectorOptions options;
  size_t selected = 0;
  for (auto _ : state) {
    const std::vector<SelectedPixel> pixels = select(pyramid, mask, options);
    selected = pixels.size();
    benchmark::DoNotOptimize(pixels.data());
  }
  state.counters["selected"] = static_cast<double>(selected);
}

void BM_SelectPixels(benchmark::State& state) { runSelection(state, selectPixels); }
void BM_SelectPixelsReference(benchmark::State& state) {
  runSelection(state, reference::selectPixels);
}
// Step 1 alone: the block medians of ‖∇I‖ (a quarter of a selection before the radix select).
template <typename ThresholdMap>
void runThresholds(benchmark::State& state, const ThresholdMap& thresholds) {
  const bench::BenchmarkRoom room;
  const ImagePyramid pyramid(room.render(room.start), 4);
  const Mask mask = validityMask(room.camera);
  const ImageGradients& g = pyramid.gradients(0);
  Image<float> norm(g.dx.width(), g.dx.height());
  for (size_t i = 0; i < norm.size(); ++i)
    norm.data()[i] = std::sqrt(g.dx.data()[i] * g.dx.data()[i] + g.dy.data()[i] * g.dy.data()[i]);
  for (auto _ : state) benchmark::DoNotOptimize(thresholds(norm, mask, 32, 7.0).data());
}
void BM_ThresholdMap(benchmark::State& state) { runThresholds(state, gradientThresholdMap); }
void BM_ThresholdMapReference(benchmark::State& state) {
  runThresholds(state, reference::gradientThresholdMap);
}

BENCHMARK(BM_SelectPixels)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelectPixelsReference)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ThresholdMap)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ThresholdMapReference)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace omnidso
