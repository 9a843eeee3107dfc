// A frame's image preparation on a 480×480 fisheye frame, as `omnidso run` does it per frame:
// the photometric correction of the raw 8-bit image (G⁻¹ and the vignette), then the 4-level
// pyramid with its gradients (docs/performance.md, "Candidate selection and image
// preparation"). Each benchmark has a *Reference twin running the implementation it replaced
// (tests/support/reference_image_preparation.hpp, the same bits), for side-by-side ratios.
#include <benchmark/benchmark.h>

#include <cmath>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/core/pyramid.hpp>

#include "benchmark_room.hpp"
#include "support/reference_image_preparation.hpp"

namespace omnidso {
namespace {

// The rendered room as the camera would record it: a gamma response, a radial vignette that
// is zero outside the image circle, values rounded to 8 bits.
struct RawFrame {
  PhotometricCalibration calibration;
  RawImage raw;
  ImageF energy;

  RawFrame() {
    const bench::BenchmarkRoom room;
    const ImageF radiance = room.render(room.start);
    InverseResponse g;
    for (int k = 0; k < kResponseSize; ++k) g[k] = 255.0 * std::pow(k / 255.0, 2.2);
    const int w = radiance.width(), h = radiance.height();
    ImageF vignette(w, h);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const double r = std::hypot(u - (w - 1) / 2.0, v - (h - 1) / 2.0) / (w / 2.0);
        vignette(u, v) = r < 1.0 ? static_cast<float>(1.0 - 0.4 * r * r) : 0.0f;
      }
    calibration = PhotometricCalibration(g, vignette);
    raw = RawImage{8, ImageU16(w, h)};
    for (std::size_t i = 0; i < radiance.size(); ++i) {
      const double value = calibration.response(vignette.data()[i] * radiance.data()[i]);
      raw.pixels.data()[i] = static_cast<std::uint16_t>(std::lround(value));
    }
    energy = calibration.correct(raw);
  }
};

void BM_PhotometricCorrect(benchmark::State& state) {
  const RawFrame f;
  for (auto _ : state) benchmark::DoNotOptimize(f.calibration.correct(f.raw).data());
}
void BM_PhotometricCorrectReference(benchmark::State& state) {
  const RawFrame f;
  for (auto _ : state)
    benchmark::DoNotOptimize(reference::correct(f.calibration, f.raw).data());
}

void BM_ComputeGradients(benchmark::State& state) {
  const RawFrame f;
  for (auto _ : state) benchmark::DoNotOptimize(computeGradients(f.energy).dx.data());
}
void BM_ComputeGradientsReference(benchmark::State& state) {
  const RawFrame f;
  for (auto _ : state) benchmark::DoNotOptimize(reference::computeGradients(f.energy).dx.data());
}

// ImagePyramid takes its level 0 by value, as the odometry's copy of the frame.
void BM_ImagePyramid(benchmark::State& state) {
  const RawFrame f;
  for (auto _ : state) {
    const ImagePyramid pyramid(f.energy, 4);
    benchmark::DoNotOptimize(pyramid.gradients(3).dx.data());
  }
}
void BM_ImagePyramidReference(benchmark::State& state) {
  const RawFrame f;
  for (auto _ : state) {
    const reference::Pyramid pyramid(f.energy, 4);
    benchmark::DoNotOptimize(pyramid.gradients[3].dx.data());
  }
}

BENCHMARK(BM_PhotometricCorrect)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PhotometricCorrectReference)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ComputeGradients)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ComputeGradientsReference)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ImagePyramid)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ImagePyramidReference)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace omnidso
