// Candidate selection of one keyframe (selectPixels, DSO's 2000 candidates) on a rendered
// 480×480 UCM room image with the camera's validity mask: the odometry runs it once per
// keyframe (docs/performance.md, "Speed").
#include <benchmark/benchmark.h>

#include <omnidso/cameras/camera.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/bearing_table.hpp>
#include <omnidso/synth/renderer.hpp>
#include <omnidso/synth/scene.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

namespace omnidso {
namespace {

void BM_SelectPixels(benchmark::State& state) {
  const Camera camera = synth::syntheticCamera("ucm", 185.0, 480, 480);
  const synth::Scene scene = synth::makeRoomScene(synth::RoomSceneConfig{}, 3);
  const Eigen::VectorXd p = camera.params();
  synth::PhotometricModel photometric;
  photometric.noise = false;
  synth::Renderer renderer(scene, synth::makeBearingTable(camera, 480, 480, 2, p[2], p[3]),
                           photometric, 2, 3);
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d(0, -1, 0);
  R.col(1) = Eigen::Vector3d(0, 0, -1);
  R.col(2) = Eigen::Vector3d(1, 0, 0);
  ImageF image = renderer.renderRadiance({SE3d(R, scene.freeSpace().centre())});
  for (size_t i = 0; i < image.size(); ++i) image.data()[i] *= 200.f;
  const ImagePyramid pyramid(image, 4);
  const Mask mask = validityMask(camera);
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
