// Candidate selection of one keyframe (selectPixels, DSO's 2000 candidates) on a rendered
// 480×480 UCM room image with the camera's validity mask: the odometry runs it once per
// keyframe (docs/performance.md, "Speed").
#include <benchmark/benchmark.h>

#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "benchmark_room.hpp"

namespace omnidso {
namespace {

void BM_SelectPixels(benchmark::State& state) {
  const bench::BenchmarkRoom room;
  const ImagePyramid pyramid(room.render(room.start), 4);
  const Mask mask = validityMask(room.camera);
  PixelSelectorOptions options;
  size_t selected = 0;
  for (auto _ : state) {
    const std::vector<SelectedPixel> pixels = selectPixels(pyramid, mask, options);
    selected = pixels.size();
    benchmark::DoNotOptimize(pixels.data());
  }
  state.counters["selected"] = static_cast<double>(selected);
}
BENCHMARK(BM_SelectPixels)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace omnidso
