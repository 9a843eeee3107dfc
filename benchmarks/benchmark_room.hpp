#pragma once
// The rendered scene the benchmarks share: the synthetic room seen by a 185° UCM camera,
// 480×480 (the paper's resolution), noise-free, intensities 200 × radiance (the 0..255 range
// of real images), from a start pose at the room's centre looking along +x.
#include <memory>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/synth/bearing_table.hpp>
#include <omnidso/synth/renderer.hpp>
#include <omnidso/synth/scene.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

namespace omnidso::bench {

struct BenchmarkRoom {
  Camera camera = synth::syntheticCamera("ucm", 185.0, 480, 480);
  synth::Scene scene = synth::makeRoomScene(synth::RoomSceneConfig{}, 3);
  std::unique_ptr<synth::Renderer> renderer;
  SE3d start;

  BenchmarkRoom() {
    const Eigen::VectorXd p = camera.params();
    synth::PhotometricModel photometric;
    photometric.noise = false;
    renderer = std::make_unique<synth::Renderer>(
        scene, synth::makeBearingTable(camera, 480, 480, 2, p[2], p[3]), photometric, 2, 3);
    Eigen::Matrix3d R;
    R.col(0) = Eigen::Vector3d(0, -1, 0);
    R.col(1) = Eigen::Vector3d(0, 0, -1);
    R.col(2) = Eigen::Vector3d(1, 0, 0);
    start = SE3d(R, scene.freeSpace().centre());
  }

  ImageF render(const SE3d& T_world_cam) const {
    ImageF image = renderer->renderRadiance({T_world_cam});
    for (size_t i = 0; i < image.size(); ++i) image.data()[i] *= 200.f;
    return image;
  }
};

}  // namespace omnidso::bench
