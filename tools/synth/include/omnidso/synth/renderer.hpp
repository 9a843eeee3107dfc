#pragma once
// Ray-casting renderer: for every sub-pixel sample of the bearing table, rotate the bearing
// into the world by the camera pose T_world_cam, intersect the scene and average the
// radiance over the pixel (supersampled anti-aliasing), then apply the photometric model
// (photometric_model.hpp) and quantise to 8 bits.
//
// Motion blur: with several poses spread over the exposure, sample j of each pixel uses
// pose j mod P (stratified in time as in distribution ray tracing; no extra rays).
// Threads split the rows; the noise of pixel i in frame k is keyed by (seed, k, i), so the
// image is the same for any number of threads.

#include <cstdint>
#include <vector>

#include <omnidso/core/image.hpp>
#include <omnidso/core/se3.hpp>
#include <omnidso/synth/bearing_table.hpp>
#include <omnidso/synth/photometric_model.hpp>
#include <omnidso/synth/scene.hpp>

namespace omnidso::synth {

class Renderer {
 public:
  // The scene must outlive the renderer.
  Renderer(const Scene& scene, BearingTable bearings, PhotometricModel photometric,
           int threads = 2, std::uint64_t seed = 0);

  // B̄: mean radiance over each pixel's samples; samples without a ray count as 0 (light
  // outside the image circle never reaches the sensor).
  ImageF renderRadiance(const std::vector<SE3d>& poses_world_cam) const;
  // round(G(gain·t·V·B̄ + n)) with noise n keyed by (seed, frame_index, pixel).
  ImageU8 toPixels(const ImageF& radiance, double exposure_ms, std::uint64_t frame_index) const;
  ImageU8 render(const std::vector<SE3d>& poses_world_cam, double exposure_ms,
                 std::uint64_t frame_index) const {
    return toPixels(renderRadiance(poses_world_cam), exposure_ms, frame_index);
  }

  // V per pixel, 0 where no sample of the pixel has a ray.
  const ImageF& vignette() const { return vignette_; }
  const PhotometricModel& photometric() const { return photometric_; }
  const BearingTable& bearings() const { return bearings_; }
  // Mean pixel value over pixels with V > 0 (the auto-exposure's measurement).
  double meanValidPixelValue(const ImageU8& image) const;

 private:
  template <typename RowFunction>
  void forEachRow(const RowFunction& row_function) const;

  const Scene& scene_;
  BearingTable bearings_;
  PhotometricModel photometric_;
  int threads_;
  std::uint64_t seed_;
  ImageF vignette_;
};

}  // namespace omnidso::synth
