#pragma once
// Rendered test scenes: the synthetic room (omnidso::synth) seen through any camera, with
// noise-free radiance images and ground-truth distances by ray casting — for tests of the
// window, the tracker and the epipolar search that need real images with known geometry.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/pyramid.hpp>
#include <omnidso/synth/bearing_table.hpp>
#include <omnidso/synth/renderer.hpp>
#include <omnidso/synth/scene.hpp>
#include <optional>

namespace omnidso::test {

class RenderedScene {
 public:
  // Intensities are 200 × radiance (radiance ≈ 0..1): the 0..255 range of real images.
  static constexpr double kIntensityScale = 200.0;

  RenderedScene(const Camera& camera, std::uint64_t seed)
      : camera_(camera), scene_(synth::makeRoomScene(synth::RoomSceneConfig{}, seed)) {
    const Eigen::VectorXd p = camera.params();
    synth::PhotometricModel photometric;
    photometric.noise = false;
    renderer_ = std::make_unique<synth::Renderer>(
        scene_, synth::makeBearingTable(camera, camera.width(), camera.height(), 2, p[2], p[3]),
        photometric, 2, seed);
  }

  const Camera& camera() const { return camera_; }
  const synth::Scene& scene() const { return scene_; }

  // blur_sigma_px > 0: a Gaussian lens blur (real optics are never box-filter sharp; the
  // renderer's textures have step edges whose aliasing makes the photometric energy rough).
  ImageF render(const SE3d& T_world_cam, double blur_sigma_px = 0.0) const {
    ImageF image = renderer_->renderRadiance({T_world_cam});
    for (size_t i = 0; i < image.size(); ++i)
      image.data()[i] = static_cast<float>(kIntensityScale * image.data()[i]);
    return blur_sigma_px > 0 ? gaussianBlur(image, blur_sigma_px) : image;
  }

  std::shared_ptr<const ImagePyramid> renderPyramid(const SE3d& T_world_cam, int levels = 5,
                                                    double blur_sigma_px = 0.0) const {
    return std::make_shared<const ImagePyramid>(render(T_world_cam, blur_sigma_px), levels);
  }

  // Separable Gaussian, borders clamped.
  static ImageF gaussianBlur(const ImageF& in, double sigma) {
    const int radius = static_cast<int>(std::ceil(3 * sigma));
    std::vector<float> k(2 * radius + 1);
    float sum = 0.f;
    for (int i = -radius; i <= radius; ++i) sum += k[i + radius] = std::exp(-0.5f * i * i / float(sigma * sigma));
    for (float& v : k) v /= sum;
    const int w = in.width(), h = in.height();
    ImageF tmp(w, h), out(w, h);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        float acc = 0.f;
        for (int i = -radius; i <= radius; ++i) acc += k[i + radius] * in(std::clamp(u + i, 0, w - 1), v);
        tmp(u, v) = acc;
      }
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        float acc = 0.f;
        for (int i = -radius; i <= radius; ++i) acc += k[i + radius] * tmp(u, std::clamp(v + i, 0, h - 1));
        out(u, v) = acc;
      }
    return out;
  }

  // Distance along the unit bearing (camera frame) to the first surface.
  std::optional<double> distance(const SE3d& T_world_cam, const Eigen::Vector3d& bearing) const {
    synth::RayHit hit;
    const Eigen::Vector3d direction = T_world_cam.rotation() * bearing;
    if (!scene_.intersect(T_world_cam.translation().cast<float>(), direction.cast<float>(), &hit))
      return std::nullopt;
    return static_cast<double>(hit.distance);
  }

  // A camera at the centre of the scene's free space, looking along +x with z up
  // (camera x right, y down, z forward).
  SE3d centralPose() const {
    Eigen::Matrix3d R_world_cam;
    R_world_cam.col(0) = Eigen::Vector3d(0, -1, 0);
    R_world_cam.col(1) = Eigen::Vector3d(0, 0, -1);
    R_world_cam.col(2) = Eigen::Vector3d(1, 0, 0);
    return SE3d(R_world_cam, scene_.freeSpace().centre());
  }

 private:
  Camera camera_;
  synth::Scene scene_;
  std::unique_ptr<synth::Renderer> renderer_;
};

// T · exp([rho; phi]) with rho in metres and phi in degrees (camera frame).
inline SE3d moveInCamera(const SE3d& T, const Eigen::Vector3d& rho, const Eigen::Vector3d& phi_deg) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << rho, phi_deg * M_PI / 180.0;
  return T * SE3d::exp(xi);
}

}  // namespace omnidso::test
