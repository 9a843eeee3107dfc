// The ray-casting renderer; the model is in renderer.hpp and photometric_model.hpp.
#include <omnidso/synth/renderer.hpp>

#include <algorithm>
#include <cmath>
#include <thread>

#include <omnidso/synth/random.hpp>

namespace omnidso::synth {

Renderer::Renderer(const Scene& scene, BearingTable bearings, PhotometricModel photometric,
                   int threads, std::uint64_t seed)
    : scene_(scene),
      bearings_(std::move(bearings)),
      photometric_(photometric),
      threads_(std::max(1, threads)),
      seed_(seed),
      vignette_(bearings_.width, bearings_.height, 0.f) {
  const int per_pixel = bearings_.samplesPerPixel();
  for (int v = 0; v < bearings_.height; ++v) {
    for (int u = 0; u < bearings_.width; ++u) {
      const size_t first = (static_cast<size_t>(v) * bearings_.width + u) * per_pixel;
      const bool any_ray =
          std::any_of(bearings_.bearings.begin() + static_cast<std::ptrdiff_t>(first),
                      bearings_.bearings.begin() + static_cast<std::ptrdiff_t>(first + per_pixel),
                      [](const Eigen::Vector3f& b) { return b.squaredNorm() > 0.f; });
      if (any_ray) {
        vignette_(u, v) = static_cast<float>(photometric_.vignette(
            u, v, bearings_.width, bearings_.height, bearings_.cx, bearings_.cy));
      }
    }
  }
}

template <typename RowFunction>
void Renderer::forEachRow(const RowFunction& row_function) const {
  // Interleaved rows balance the load (a fisheye's image circle leaves corner rows short).
  auto worker = [&](int first) {
    for (int v = first; v < bearings_.height; v += threads_) row_function(v);
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < threads_; ++k) pool.emplace_back(worker, k);
  worker(0);
  for (std::thread& thread : pool) thread.join();
}

ImageF Renderer::renderRadiance(const std::vector<SE3d>& poses_world_cam) const {
  std::vector<Eigen::Matrix3f> rotations;
  std::vector<Scene::PreparedOrigin> origins;
  for (const SE3d& pose : poses_world_cam) {
    rotations.push_back(pose.rotationMatrix().cast<float>());
    origins.push_back(scene_.prepare(pose.translation().cast<float>()));
  }
  const int num_poses = static_cast<int>(rotations.size());
  const int per_pixel = bearings_.samplesPerPixel();
  const float inv_per_pixel = 1.f / static_cast<float>(per_pixel);
  ImageF radiance(bearings_.width, bearings_.height, 0.f);
  forEachRow([&](int v) {
    float* out = radiance.row(v);
    const Eigen::Vector3f* bearing =
        bearings_.bearings.data() + static_cast<size_t>(v) * bearings_.width * per_pixel;
    RayHit hit;
    for (int u = 0; u < bearings_.width; ++u) {
      float sum = 0.f;
      for (int j = 0; j < per_pixel; ++j, ++bearing) {
        if (bearing->squaredNorm() == 0.f) continue;
        const int p = j % num_poses;
        if (scene_.intersect(origins[static_cast<size_t>(p)],
                             rotations[static_cast<size_t>(p)] * *bearing, &hit)) {
          sum += scene_.radiance(hit);
        }
      }
      out[u] = sum * inv_per_pixel;
    }
  });
  return radiance;
}

ImageU8 Renderer::toPixels(const ImageF& radiance, double exposure_ms,
                           std::uint64_t frame_index) const {
  ImageU8 image(radiance.width(), radiance.height(), 0);
  const double scale = photometric_.gain_per_ms * exposure_ms;
  forEachRow([&](int v) {
    for (int u = 0; u < radiance.width(); ++u) {
      const double vignette = vignette_(u, v);
      if (vignette <= 0.0) continue;  // no light: black outside the image circle
      double irradiance = scale * vignette * radiance(u, v);
      if (photometric_.noise) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(v) * radiance.width() + u;
        irradiance += photometric_.noiseSigma(irradiance) *
                      gaussianFromBits(counterHash(seed_, frame_index, pixel));
      }
      const double value = std::round(photometric_.response(irradiance));
      image(u, v) = static_cast<std::uint8_t>(std::clamp(value, 0.0, 255.0));
    }
  });
  return image;
}

double Renderer::meanValidPixelValue(const ImageU8& image) const {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    if (vignette_.data()[i] > 0.f) {
      sum += image.data()[i];
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace omnidso::synth
